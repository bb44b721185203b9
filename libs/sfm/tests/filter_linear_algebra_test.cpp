// The filter's covariance downdate against the textbook P - PHt S^-1 PHt^T, at sizes that take
// the direct triangular solve, its split into halves, and uneven splits; the products with H's
// point blocks against dense ones.

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

// The point blocks of H (two rows per measurement, three columns per point) against the products
// with H written out dense, points measured in shuffled order.
TEST(FilterLinearAlgebra, PointBlocksMatchTheDenseProducts) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0, 1);
  const int points = 9, n = 6 + 3 * points;
  const Eigen::MatrixXd P = random_covariance(n, rng);
  const std::vector<int> slots = {4, 0, 7, 2, 8};
  const int m = static_cast<int>(slots.size());
  std::vector<int> first_column;
  std::vector<Eigen::Matrix<double, 2, 3>> H_point;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * m, n);
  for (int k = 0; k < m; ++k) {
    first_column.push_back(6 + 3 * slots[k]);
    H_point.push_back(Eigen::Matrix<double, 2, 3>::NullaryExpr([&] { return normal(rng); }));
    H.block<2, 3>(2 * k, first_column.back()) = H_point.back();
  }
  const Eigen::MatrixXd offset = Eigen::MatrixXd::NullaryExpr(n, 2 * m, [&] { return normal(rng); });
  Eigen::MatrixXd PHt = offset;
  add_point_columns(P, first_column, H_point, &PHt);
  EXPECT_LT((PHt - (offset + P * H.transpose())).norm(), 1e-12 * PHt.norm());

  const Eigen::MatrixXd S0 = Eigen::MatrixXd::NullaryExpr(2 * m, 2 * m, [&] { return normal(rng); });
  Eigen::MatrixXd S = S0;
  add_point_rows_lower(PHt, first_column, H_point, &S);
  const Eigen::MatrixXd expected = S0 + H * PHt;
  EXPECT_LT((S.triangularView<Eigen::Lower>().toDenseMatrix() -
             expected.triangularView<Eigen::Lower>().toDenseMatrix()).norm(),
            1e-12 * expected.norm());
}

TEST(FilterLinearAlgebra, CholeskyRefusesAnIndefiniteMatrix) {
  Eigen::MatrixXd S = Eigen::Matrix2d{{1, 2}, {2, 1}};
  EXPECT_FALSE(cholesky_lower_in_place(&S));
}

}  // namespace
}  // namespace omnisfm::sfm
