#include "filter_linear_algebra.h"

#include <Eigen/LU>
#include <cmath>

#include <algorithm>
#include <cstdlib>

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
}

namespace omnisfm::sfm {
namespace {

// B := B L^-T for B (rows x cols, leading dimension ldb) and L lower triangular (cols x cols).
// Split L = [L11 0; L21 L22]: B1 := B1 L11^-T, then B2 := (B2 - B1 L21^T) L22^-T. Most of the
// work becomes matrix products, which OpenBLAS runs near the CPU's peak, where its own
// right-side triangular solve runs at a third of that.
void solve_right_lower_transposed(int rows, int cols, const double* L, int ldl, double* B,
                                  int ldb) {
  const double one = 1, minus_one = -1;
  constexpr int kDirectColumns = 16;
  if (cols <= kDirectColumns) {
    dtrsm_("R", "L", "T", "N", &rows, &cols, &one, L, &ldl, B, &ldb);
    return;
  }
  const int first = cols / 2, second = cols - first;
  double* B2 = B + static_cast<long>(first) * ldb;
  solve_right_lower_transposed(rows, first, L, ldl, B, ldb);
  dgemm_("N", "T", &rows, &second, &first, &minus_one, B, &ldb, L + first, &ldl, &one, B2, &ldb);
  solve_right_lower_transposed(rows, second, L + first + static_cast<long>(first) * ldl, ldl, B2,
                               ldb);
}

// The strict upper triangle := the lower one's transpose, by square tiles that stay in cache.
void mirror_lower(Eigen::MatrixXd* P) {
  constexpr int kTile = 32;
  const int n = static_cast<int>(P->rows());
  for (int c0 = 0; c0 < n; c0 += kTile)
    for (int r0 = 0; r0 <= c0; r0 += kTile) {
      const int c1 = std::min(n, c0 + kTile), r1 = std::min(n, r0 + kTile);
      for (int col = c0; col < c1; ++col)
        for (int row = r0; row < std::min(r1, col); ++row) (*P)(row, col) = (*P)(col, row);
    }
}

}  // namespace

void multiply(const Eigen::Ref<const Eigen::MatrixXd>& A, bool transpose_A,
              const Eigen::Ref<const Eigen::MatrixXd>& B, bool transpose_B,
              Eigen::Ref<Eigen::MatrixXd> C) {
  const int m = static_cast<int>(C.rows()), n = static_cast<int>(C.cols());
  const int k = static_cast<int>(transpose_A ? A.rows() : A.cols());
  if (m == 0 || n == 0) return;
  const int lda = static_cast<int>(A.outerStride()), ldb = static_cast<int>(B.outerStride());
  const int ldc = static_cast<int>(C.outerStride());
  const double one = 1, zero = 0;
  dgemm_(transpose_A ? "T" : "N", transpose_B ? "T" : "N", &m, &n, &k, &one, A.data(), &lda,
         B.data(), &ldb, &zero, C.data(), &ldc);
}

bool cholesky_lower_in_place(Eigen::MatrixXd* S) {
  const int n = static_cast<int>(S->rows());
  if (n == 0) return true;
  int info = 0;
  dpotrf_("L", &n, S->data(), &n, &info);
  return info == 0;
}

void downdate_covariance(Eigen::MatrixXd* P, Eigen::MatrixXd* PHt, const Eigen::MatrixXd& L) {
  const int n = static_cast<int>(P->rows());
  const int m = static_cast<int>(L.rows());
  if (m == 0 || n == 0) return;
  // W = PHt L^-T, then P -= W W^T on the lower triangle (a symmetric rank-m update), mirrored.
  // Solving from the right on the tall PHt runs about twice as fast as from the left on its
  // transpose.
  const double one = 1, minus_one = -1;
  solve_right_lower_transposed(n, m, L.data(), m, PHt->data(), n);
  dsyrk_("L", "N", &n, &m, &minus_one, PHt->data(), &n, &one, P->data(), &n);
  mirror_lower(P);
}

// Column by column, so that every operation runs down contiguous memory; Eigen's product of a
// 2 x kPointSize matrix and a strided block does not vectorise.
void add_point_columns(const Eigen::MatrixXd& P, const std::vector<int>& first_column,
                       const std::vector<PointRows>& H_point, Eigen::MatrixXd* PHt) {
  constexpr int kSize = FilterState::kPointSize;
  const Eigen::Index n = P.rows();
  for (size_t k = 0; k < H_point.size(); ++k) {
    const PointRows& h = H_point[k];
    double* out0 = PHt->col(2 * k).data();
    double* out1 = PHt->col(2 * k + 1).data();
    for (int j = 0; j < kSize; ++j) {
      const double h0 = h(0, j), h1 = h(1, j);
      const double* p = P.col(first_column[k] + j).data();
      for (Eigen::Index i = 0; i < n; ++i) {
        out0[i] += h0 * p[i];
        out1[i] += h1 * p[i];
      }
    }
  }
}

void add_point_rows_lower(const Eigen::MatrixXd& PHt, const std::vector<int>& first_column,
                          const std::vector<PointRows>& H_point, Eigen::MatrixXd* S) {
  const Eigen::Index columns = S->cols();
  for (Eigen::Index j = 0; j < columns; ++j) {
    const double* phT = PHt.col(j).data();
    double* s = S->col(j).data();
    for (size_t k = static_cast<size_t>(j / 2); k < H_point.size(); ++k) {
      const Eigen::Map<const Eigen::Matrix<double, FilterState::kPointSize, 1>> x(
          phT + first_column[k]);
      const Eigen::Vector2d hx = H_point[k] * x;
      s[2 * k] += hx[0];
      s[2 * k + 1] += hx[1];
    }
  }
}

std::vector<double> posterior_chi2(const Eigen::MatrixXd& L, const Eigen::VectorXd& residual,
                                   double variance, const Eigen::MatrixXd* unestimated) {
  const int m = static_cast<int>(residual.size()) / 2;
  std::vector<double> chi2(m);
  if (unestimated) {
    // (M S^-1 M^T)_kk = Y_k^T Y_k with Y = L^-1 M^T, column block k.
    Eigen::MatrixXd Y = unestimated->transpose();
    Y.diagonal().array() += variance;
    L.triangularView<Eigen::Lower>().solveInPlace(Y);
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector2d r = residual.segment<2>(2 * k);
      const auto Y_k = Y.middleCols<2>(2 * k);
      const Eigen::Matrix2d covariance = Y_k.transpose() * Y_k;
      chi2[k] = r.allFinite() ? r.dot(covariance.inverse() * r) : INFINITY;
    }
    return chi2;
  }
  // (S^-1)_kk = X_k^T X_k with X = L^-1, whose column block k is zero above row 2k.
  Eigen::MatrixXd X = Eigen::MatrixXd::Identity(2 * m, 2 * m);
  L.triangularView<Eigen::Lower>().solveInPlace(X);
  for (int k = 0; k < m; ++k) {
    const Eigen::Vector2d r = residual.segment<2>(2 * k);
    if (!r.allFinite()) {
      chi2[k] = INFINITY;
      continue;
    }
    const auto X_k = X.block(2 * k, 2 * k, 2 * m - 2 * k, 2);
    const Eigen::Matrix2d covariance = variance * variance * (X_k.transpose() * X_k);
    chi2[k] = r.dot(covariance.inverse() * r);
  }
  return chi2;
}

}  // namespace omnisfm::sfm
