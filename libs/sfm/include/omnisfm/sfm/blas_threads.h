#pragma once
// OpenBLAS's threads spin while they wait: for the online filter's matrices, a few hundred rows,
// they gain little, and when the other cores are busy (Ceres' threads, another process) a frame
// takes several times longer. The thread count is the process's, so the libraries leave it alone:
// a program that runs the filter calls this once at its start (the omnisfm command and
// omnisfm-slam do; the tests set OPENBLAS_NUM_THREADS=1).

namespace omnisfm::sfm {

// Sets OpenBLAS to one thread, unless OPENBLAS_NUM_THREADS or OMP_NUM_THREADS chose a count or
// the BLAS is another library. Returns whether it set it.
bool use_one_blas_thread();

}  // namespace omnisfm::sfm
