// The size the long checks (CTest label `long`) run at: small by default, as CI runs them within
// its time; with OMNISFM_TEST_SIZE=full the seeds and drives the documents quote.
#pragma once

#include <cstdlib>
#include <cstring>

namespace omnisfm::sfm {

inline bool full_size_checks() {
  const char* size = std::getenv("OMNISFM_TEST_SIZE");
  return size != nullptr && std::strcmp(size, "full") == 0;
}

template <typename T>
T small_or_full(T small, T full) {
  return full_size_checks() ? full : small;
}

}  // namespace omnisfm::sfm
