#include "omnisfm/core/mahalanobis.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnisfm::core {
namespace {

TEST(Mahalanobis, SigmasAlongTheErrorsDirection) {
  Eigen::MatrixXd covariance(2, 2);
  covariance << 4, 0, 0, 9;
  EXPECT_DOUBLE_EQ(mahalanobis(Eigen::Vector2d(2, 0), covariance), 1);
  EXPECT_DOUBLE_EQ(mahalanobis(Eigen::Vector2d(0, -6), covariance), 2);
  // Correlated: e^T C^-1 e by hand for C = [[2, 1], [1, 2]], e = (1, 1): 2/3.
  covariance << 2, 1, 1, 2;
  EXPECT_NEAR(mahalanobis(Eigen::Vector2d(1, 1), covariance), std::sqrt(2.0 / 3), 1e-15);
  covariance << 1, 0, 0, 0;  // a parameter known exactly: no sigma to count in
  EXPECT_TRUE(std::isnan(mahalanobis(Eigen::Vector2d(1, 1), covariance)));
}

}  // namespace
}  // namespace omnisfm::core
