#pragma once
// How many threads a Ceres solve of `residuals` residuals runs on, for the batch and the
// calibration alike.

#include <algorithm>
#include <cstddef>
#include <thread>

namespace omnisfm::core {

// Problems under this many residuals run on one thread, as COLMAP's bundle adjuster does below its
// own threshold: each of Ceres' steps must have enough work to split, and one thread gives the
// same digits on every run (several add their shares in whatever order they finish: a checkerboard
// calibration's focal length moved by 0.06 px between runs on two). The figure is a rule of thumb.
constexpr std::size_t kSmallProblemResiduals = 5000;

// `requested` when above 0 (a caller's setting), else one for a small problem and one per core
// for a larger one.
inline int solver_threads(int requested, std::size_t residuals) {
  if (requested > 0) return requested;
  if (residuals < kSmallProblemResiduals) return 1;
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace omnisfm::core
