// The filter's covariance downdate against the textbook P - PHt S^-1 PHt^T, at sizes that take
// the direct triangular solve, its split into halves, and uneven splits.

#include "../src/filter_linear_algebra.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

namespace omnisfm::sfm {
namespace {

Eigen::MatrixXd random_covariance(int n, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0, 1);
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(rng); });
  return A * A.transpose() + n * Eigen::MatrixXd::Identity(n, n);
}

TEST(FilterLinearAlgebra, DowndateMatchesTheTextbookFormula) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal(0, 1);
  for (const auto& [n, m] : {std::pair{9, 2}, {36, 16}, {37, 17}, {96, 60}, {342, 224}, {35, 71}}) {
    const Eigen::MatrixXd P = random_covariance(n, rng);
    const Eigen::MatrixXd H = Eigen::MatrixXd::NullaryExpr(m, n, [&] { return normal(rng); });
    Eigen::MatrixXd S = H * P * H.transpose();
    S.diagonal().array() += 0.09;
    const Eigen::MatrixXd expected = P - P * H.transpose() * S.ldlt().solve(H * P);

    Eigen::MatrixXd P_downdated = P;
    Eigen::MatrixXd PHt = P * H.transpose();
    Eigen::MatrixXd L = S;
    ASSERT_TRUE(cholesky_lower_in_place(&L));
    downdate_covariance(&P_downdated, &PHt, L);
    SCOPED_TRACE(testing::Message() << "n " << n << " m " << m);
    EXPECT_LT((P_downdated - expected).norm(), 1e-9 * P.norm());
    EXPECT_EQ((P_downdated - P_downdated.transpose()).norm(), 0.0);
  }
}

TEST(FilterLinearAlgebra, CholeskyRefusesAnIndefiniteMatrix) {
  Eigen::MatrixXd S = Eigen::Matrix2d{{1, 2}, {2, 1}};
  EXPECT_FALSE(cholesky_lower_in_place(&S));
}

}  // namespace
}  // namespace omnisfm::sfm
