#include "dense_covariance.h"

extern "C" {
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m,
            const int* n, const double* alpha, const double* a, const int* lda, double* b,
            const int* ldb);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
}

namespace omnisfm::sfm {

bool cholesky_lower_in_place(Eigen::MatrixXd* S) {
  const int n = static_cast<int>(S->rows());
  if (n == 0) return true;
  int info = 0;
  dpotrf_("L", &n, S->data(), &n, &info);
  return info == 0;
}

void downdate_covariance(Eigen::MatrixXd* P, const Eigen::MatrixXd& PHt, const Eigen::MatrixXd& L) {
  const int n = static_cast<int>(P->rows());
  const int m = static_cast<int>(L.rows());
  if (m == 0 || n == 0) return;
  // W = L^-1 PHt^T, then P -= W^T W on the lower triangle (a symmetric rank-m update), mirrored.
  Eigen::MatrixXd W = PHt.transpose();
  const double one = 1, minus_one = -1;
  dtrsm_("L", "L", "N", "N", &m, &n, &one, L.data(), &m, W.data(), &m);
  dsyrk_("L", "T", &n, &m, &minus_one, W.data(), &m, &one, P->data(), &n);
  for (int col = 1; col < n; ++col)
    for (int row = 0; row < col; ++row) (*P)(row, col) = (*P)(col, row);
}

}  // namespace omnisfm::sfm
