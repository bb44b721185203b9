#pragma once
// The filter's dense linear algebra through LAPACK and BLAS: the innovation covariance's
// Cholesky factor and the covariance downdate. With a tuned BLAS (OpenBLAS picks its kernels for
// the CPU it runs on) these run several times faster than Eigen's portable SSE2 code, and they
// are most of a frame's work.

#include <Eigen/Core>

namespace omnisfm::sfm {

// S := its lower Cholesky factor (the strict upper triangle is left as it was). False when S is
// not positive definite.
bool cholesky_lower_in_place(Eigen::MatrixXd* S);

// P := P - PHt S^-1 PHt^T, with L the lower Cholesky factor of S; P stays symmetric.
void downdate_covariance(Eigen::MatrixXd* P, const Eigen::MatrixXd& PHt, const Eigen::MatrixXd& L);

}  // namespace omnisfm::sfm
