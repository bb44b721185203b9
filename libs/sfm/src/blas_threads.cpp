#include "omnisfm/sfm/blas_threads.h"

#include <dlfcn.h>

#include <cstdlib>

namespace omnisfm::sfm {

bool use_one_blas_thread() {
  if (std::getenv("OPENBLAS_NUM_THREADS") || std::getenv("OMP_NUM_THREADS")) return false;
  using SetThreads = void (*)(int);
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!set) return false;
  set(1);
  return true;
}

}  // namespace omnisfm::sfm
