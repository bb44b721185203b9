// The filter's covariance downdate against the textbook P - PHt S^-1 PHt^T, at sizes that take
// the direct triangular solve, its split into halves, and uneven splits; the products with H's
// point blocks against dense ones. The algebra leaves OpenBLAS's threads as the program set
// them; use_one_blas_thread is the programs' to call.

#include "../src/filter_linear_algebra.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>

#include "omnisfm/sfm/blas_threads.h"
#include "scoped_environment.h"

namespace omnisfm::sfm {
namespace {

Eigen::MatrixXd random_covariance(int n, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0, 1);
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(rng); });
  return A * A.transpose() + n * Eigen::MatrixXd::Identity(n, n);
}

// Over draws of a linear model (truth x ~ N(0, P), z = H x + noise of `variance`, the prior
// mean 0), the mean per measurement of score(z - H gain z); with `check`, the first draws' scores
// also against the Mahalanobis distances under `residual_covariance`.
double mean_score(const Eigen::MatrixXd& P, const Eigen::MatrixXd& H, const Eigen::MatrixXd& gain,
                  double variance, const Eigen::MatrixXd& residual_covariance, bool check,
                  const std::function<std::vector<double>(const Eigen::VectorXd&)>& score,
                  std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0, 1);
  const Eigen::LLT<Eigen::MatrixXd> P_factor(P);
  const auto n = P.rows();
  const int m = static_cast<int>(H.rows()) / 2;
  double mean = 0;
  const int draws = 4000;
  for (int draw = 0; draw < draws; ++draw) {
    Eigen::VectorXd x = P_factor.matrixL() * Eigen::VectorXd::NullaryExpr(n, [&] { return normal(rng); });
    Eigen::VectorXd z = H * x;
    for (int i = 0; i < 2 * m; ++i) z[i] += std::sqrt(variance) * normal(rng);
    const Eigen::VectorXd residual = z - H * (gain * z);
    const std::vector<double> chi2 = score(residual);
    for (int k = 0; k < m; ++k) {
      const Eigen::Vector2d r = residual.segment<2>(2 * k);
      const Eigen::Matrix2d C = residual_covariance.block<2, 2>(2 * k, 2 * k);
      if (check && draw < 3) {
        EXPECT_NEAR(chi2[k], r.dot(C.ldlt().solve(r)), 1e-6 * (1 + chi2[k]));
      }
      mean += chi2[k] / (draws * m);
    }
  }
  return mean;
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

// The point blocks of H (two rows per measurement, kPointSize columns per point) against the products
// with H written out dense, points measured in shuffled order.
TEST(FilterLinearAlgebra, PointBlocksMatchTheDenseProducts) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0, 1);
  constexpr int kSize = FilterState::kPointSize;
  const int points = 9, n = 6 + kSize * points;
  const Eigen::MatrixXd P = random_covariance(n, rng);
  const std::vector<int> slots = {4, 0, 7, 2, 8};
  const int m = static_cast<int>(slots.size());
  std::vector<int> first_column;
  std::vector<PointRows> H_point;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * m, n);
  for (int k = 0; k < m; ++k) {
    first_column.push_back(6 + kSize * slots[k]);
    H_point.push_back(PointRows::NullaryExpr([&] { return normal(rng); }));
    H.block<2, kSize>(2 * k, first_column.back()) = H_point.back();
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

// Against the residual covariance formed directly, R - H P+ H^T with P+ = P - P H^T S^-1 H P (a
// difference that loses digits: agreement to 1e-6); and
// over draws of a linear model its mean is the 2 degrees of freedom.
TEST(FilterLinearAlgebra, PosteriorChi2MatchesTheResidualCovariance) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0, 1);
  const int n = 21, m = 8;
  const double variance = 0.09;
  const Eigen::MatrixXd P = random_covariance(n, rng);
  const Eigen::MatrixXd H = Eigen::MatrixXd::NullaryExpr(2 * m, n, [&] { return normal(rng); });
  Eigen::MatrixXd S = H * P * H.transpose();
  S.diagonal().array() += variance;
  const Eigen::MatrixXd gain = P * H.transpose() * S.inverse();
  const Eigen::MatrixXd P_posterior = P - gain * H * P;
  const Eigen::MatrixXd residual_covariance =
      variance * Eigen::MatrixXd::Identity(2 * m, 2 * m) - H * P_posterior * H.transpose();
  Eigen::MatrixXd L = S;
  ASSERT_TRUE(cholesky_lower_in_place(&L));
  const double mean = mean_score(
      P, H, gain, variance, residual_covariance, true,
      [&](const Eigen::VectorXd& r) { return posterior_chi2(L, r, variance); }, rng);
  // The mean of 32,000 chi-square(2) draws (standard deviation 2 each, correlated within a draw):
  // 2 within a few hundredths.
  EXPECT_NEAR(mean, 2.0, 0.06);
  Eigen::VectorXd residual = Eigen::VectorXd::Zero(2 * m);
  residual[3] = INFINITY;
  EXPECT_TRUE(std::isinf(posterior_chi2(L, residual, variance)[1]));
}

// Schmidt's update, the last k of the state considered (their gain zero): against the residual's
// covariance formed directly, (I - H K) S (I - H K)^T with K = [K_x; 0]; over draws its mean is 2;
// and the full update's formula, which the considered parameters' share of S would break, is
// off.
TEST(FilterLinearAlgebra, PosteriorChi2WithConsideredParameters) {
  std::mt19937_64 rng(6);
  std::normal_distribution<double> normal(0, 1);
  const int n = 21, k = 5, m = 8;
  const double variance = 0.09;
  const Eigen::MatrixXd P = random_covariance(n, rng);
  const Eigen::MatrixXd H = Eigen::MatrixXd::NullaryExpr(2 * m, n, [&] { return normal(rng); });
  Eigen::MatrixXd S = H * P * H.transpose();
  S.diagonal().array() += variance;
  const Eigen::MatrixXd PHt = P * H.transpose();
  Eigen::MatrixXd gain = PHt * S.inverse();
  gain.bottomRows(k).setZero();
  const Eigen::MatrixXd unexplained = Eigen::MatrixXd::Identity(2 * m, 2 * m) - H * gain;
  const Eigen::MatrixXd residual_covariance = unexplained * S * unexplained.transpose();
  const Eigen::MatrixXd unestimated = H.rightCols(k) * PHt.bottomRows(k);
  Eigen::MatrixXd L = S;
  ASSERT_TRUE(cholesky_lower_in_place(&L));
  const double mean = mean_score(
      P, H, gain, variance, residual_covariance, true,
      [&](const Eigen::VectorXd& r) { return posterior_chi2(L, r, variance, &unestimated); }, rng);
  const double mean_full_formula = mean_score(
      P, H, gain, variance, residual_covariance, false,
      [&](const Eigen::VectorXd& r) { return posterior_chi2(L, r, variance); }, rng);
  EXPECT_NEAR(mean, 2.0, 0.06);
  EXPECT_GT(std::abs(mean_full_formula - 2.0), 0.2);
}

TEST(FilterLinearAlgebra, CholeskyRefusesAnIndefiniteMatrix) {
  Eigen::MatrixXd S = Eigen::Matrix2d{{1, 2}, {2, 1}};
  EXPECT_FALSE(cholesky_lower_in_place(&S));
}

using test::ScopedEnvironment;

TEST(BlasThreads, TheAlgebraLeavesThemAndTheProgramSetsThem) {
  using GetThreads = int (*)();
  using SetThreads = void (*)(int);
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (!get || !set) GTEST_SKIP() << "the BLAS is not OpenBLAS: no thread count to keep";
  const int program_threads = get();
  const ScopedEnvironment openblas("OPENBLAS_NUM_THREADS", nullptr);
  const ScopedEnvironment omp("OMP_NUM_THREADS", nullptr);

  set(2);
  std::mt19937_64 rng(5);
  const Eigen::MatrixXd P = random_covariance(96, rng);
  const Eigen::MatrixXd H = Eigen::MatrixXd::Random(60, 96);
  Eigen::MatrixXd L = H * P * H.transpose() + Eigen::MatrixXd::Identity(60, 60);
  ASSERT_TRUE(cholesky_lower_in_place(&L));
  Eigen::MatrixXd P_downdated = P, PHt = P * H.transpose();
  downdate_covariance(&P_downdated, &PHt, L);
  EXPECT_EQ(get(), 2);

  EXPECT_TRUE(use_one_blas_thread());
  EXPECT_EQ(get(), 1);
  {
    const ScopedEnvironment chosen("OPENBLAS_NUM_THREADS", "2");
    set(2);
    EXPECT_FALSE(use_one_blas_thread());
    EXPECT_EQ(get(), 2);
  }
  set(program_threads);
}

}  // namespace
}  // namespace omnisfm::sfm
