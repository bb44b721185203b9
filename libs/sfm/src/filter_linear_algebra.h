#pragma once
// The filter's dense linear algebra through LAPACK and BLAS: the innovation covariance's
// Cholesky factor, the covariance downdate and the products with the pose's Jacobian columns. With a tuned BLAS (OpenBLAS picks its kernels for
// the CPU it runs on) these run several times faster than Eigen's portable SSE2 code, and they
// are most of a frame's work.

#include <Eigen/Core>
#include <vector>

#include "omnisfm/sfm/filter_state.h"

namespace omnisfm::sfm {

// C := op(A) op(B), op transposing when asked.
void multiply(const Eigen::Ref<const Eigen::MatrixXd>& A, bool transpose_A,
              const Eigen::Ref<const Eigen::MatrixXd>& B, bool transpose_B,
              Eigen::Ref<Eigen::MatrixXd> C);

// S := its lower Cholesky factor (the strict upper triangle is left as it was). False when S is
// not positive definite.
bool cholesky_lower_in_place(Eigen::MatrixXd* S);

// P := P - PHt S^-1 PHt^T, with L the lower Cholesky factor of S; P stays symmetric. PHt is
// overwritten (with PHt L^-T).
void downdate_covariance(Eigen::MatrixXd* P, Eigen::MatrixXd* PHt, const Eigen::MatrixXd& L);

// A measurement's two rows of H in its point's columns.
using PointRows = Eigen::Matrix<double, 2, FilterState::kPointSize>;

// The point columns of H, measurement k's two rows touching only P's columns first_column[k]
// onwards through H_point[k]:
// PHt.middleCols<2>(2k) += P.middleCols<kPointSize>(first_column[k]) H_point[k]^T for every k.
void add_point_columns(const Eigen::MatrixXd& P, const std::vector<int>& first_column,
                       const std::vector<PointRows>& H_point, Eigen::MatrixXd* PHt);

// S += H_points PHt on S's lower triangle, H_points as in add_point_columns.
void add_point_rows_lower(const Eigen::MatrixXd& PHt, const std::vector<int>& first_column,
                          const std::vector<PointRows>& H_point, Eigen::MatrixXd* S);

// Per measurement k (two rows each), the squared Mahalanobis distance of its residual after the
// update, r_k = z_k - h_k(x+), under that residual's covariance R - H_k P+ H_k^T =
// variance^2 (S^-1)_kk (measurement noise `variance` I): chi-square with 2 degrees of freedom for
// a measurement the model explains. L: the lower Cholesky factor of S; an infinite residual
// gives an infinite distance. With parameters the update considers but does not estimate
// (Schmidt's), `unestimated` = H_c (P H^T)_c: their gain is zero, the residual is M S^-1 y with
// M = variance I + unestimated, and its covariance M S^-1 M^T.
std::vector<double> posterior_chi2(const Eigen::MatrixXd& L, const Eigen::VectorXd& residual,
                                   double variance, const Eigen::MatrixXd* unestimated = nullptr);

}  // namespace omnisfm::sfm
