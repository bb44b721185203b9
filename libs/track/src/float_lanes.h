#pragma once
// Four floats in one register (GCC and Clang vector extensions: SSE2 on x86-64, NEON on ARM),
// for the tracker's per-pixel loops.

#include <cstring>

namespace omnisfm::track {

using Lanes = float __attribute__((vector_size(16)));
constexpr int kLanes = 4;
static_assert(sizeof(Lanes) == kLanes * sizeof(float));

inline Lanes load(const float* p) {
  Lanes l;
  std::memcpy(&l, p, sizeof l);
  return l;
}

inline void store(float* p, const Lanes& l) { std::memcpy(p, &l, sizeof l); }

}  // namespace omnisfm::track
