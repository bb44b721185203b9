// SO(3) as rotation vectors: Exp and Log invert each other (near zero and near pi too), and the
// Jacobians the motion residuals use agree with central differences of Exp and Log, on both
// sides of their small-angle series.

#include "../src/so3.h"

#include <gtest/gtest.h>

#include <random>

namespace omnisfm::sfm {
namespace {

// d/dd f(d) at d = 0 by central differences, f mapping R^3 to R^3.
template <typename F>
Eigen::Matrix3d numeric_jacobian(const F& f) {
  constexpr double kStep = 1e-6;
  Eigen::Matrix3d J;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d d = kStep * Eigen::Vector3d::Unit(i);
    J.col(i) = (f(d) - f(-d)) / (2 * kStep);
  }
  return J;
}

std::vector<Eigen::Vector3d> rotation_vectors() {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0, 1);
  std::vector<Eigen::Vector3d> ws;
  for (const double angle : {0.0, 1e-9, 1e-7, 2e-6, 1e-3, 0.3, 1.0, 2.0, 3.0, 3.1}) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d axis =
          Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
      ws.push_back(angle * axis);
    }
  }
  return ws;
}

TEST(So3, SkewIsTheCrossProduct) {
  const Eigen::Vector3d v(0.3, -1.2, 2.5), u(-0.7, 0.4, 1.1);
  EXPECT_LT((so3::skew(v) * u - v.cross(u)).norm(), 1e-15);
}

TEST(So3, LogInvertsExp) {
  for (const Eigen::Vector3d& w : rotation_vectors()) {
    const Eigen::Matrix3d R = so3::exp(w);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14) << w.transpose();
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
    EXPECT_LT((so3::log(R) - w).norm(), 1e-12 + 1e-12 * w.norm()) << w.transpose();
  }
}

TEST(So3, JacobiansAgreeWithCentralDifferences) {
  for (const Eigen::Vector3d& w : rotation_vectors()) {
    SCOPED_TRACE(testing::Message() << "w " << w.transpose());
    const Eigen::Matrix3d R = so3::exp(w);
    // Exp(w + d) = Exp(J_left(w) d) Exp(w): J_left = d Log(Exp(w + d) Exp(w)^T) / dd.
    const Eigen::Matrix3d left =
        numeric_jacobian([&](const Eigen::Vector3d& d) { return so3::log(so3::exp(w + d) * R.transpose()); });
    EXPECT_LT((so3::left_jacobian(w) - left).norm(), 1e-8);
    // Exp(w + d) = Exp(w) Exp(J_right(w) d).
    const Eigen::Matrix3d right =
        numeric_jacobian([&](const Eigen::Vector3d& d) { return so3::log(R.transpose() * so3::exp(w + d)); });
    EXPECT_LT((so3::right_jacobian(w) - right).norm(), 1e-8);
    // Log(R Exp(d)) = Log(R) + J_right(Log R)^-1 d.
    const Eigen::Matrix3d log_right =
        numeric_jacobian([&](const Eigen::Vector3d& d) { return so3::log(R * so3::exp(d)); });
    EXPECT_LT((so3::right_jacobian_inverse(w) - log_right).norm(), 1e-7 * (1 + log_right.norm()));
    EXPECT_LT((so3::right_jacobian_inverse(w) * so3::right_jacobian(w) -
               Eigen::Matrix3d::Identity()).norm(),
              1e-9);
  }
}

}  // namespace
}  // namespace omnisfm::sfm
