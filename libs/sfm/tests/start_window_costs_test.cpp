// The smoothed start's Ceres terms: their analytic Jacobians in the (w, t) pose blocks against
// numeric differentiation, away from w = 0 where J_left(w) matters.

#include "../src/start_window_costs.h"

#include <gtest/gtest.h>

#include <random>

#include "jacobian_check.h"

namespace omnisfm::sfm {
namespace {

std::vector<double> random_values(std::mt19937_64& rng, int n, double sigma) {
  std::normal_distribution<double> normal(0, sigma);
  std::vector<double> v(n);
  for (double& x : v) x = normal(rng);
  return v;
}

Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  const std::vector<double> w = random_values(rng, 3, 1);
  return so3::exp(Eigen::Vector3d(w[0], w[1], w[2]));
}

// A pixel smooth in the pose and point with exact Jacobians: M_r (R a) + M_t t + M_p point, whose
// left-perturbation rotation Jacobian is -M_r [R a]x.
struct LinearPixelModel {
  Eigen::Matrix<double, 2, 3> M_r, M_t, M_p;
  Eigen::Vector3d a;

  bool operator()(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& point,
                  bool jacobians, PixelPrediction* out) const {
    out->pixel = M_r * (R * a) + M_t * t + M_p * point;
    if (jacobians) {
      out->pose << -M_r * so3::skew(R * a), M_t;
      out->point = M_p;
    }
    return true;
  }
};

LinearPixelModel random_model(std::mt19937_64& rng) {
  LinearPixelModel m;
  m.M_r = Eigen::Matrix<double, 2, 3>::Map(random_values(rng, 6, 100).data());
  m.M_t = Eigen::Matrix<double, 2, 3>::Map(random_values(rng, 6, 100).data());
  m.M_p = Eigen::Matrix<double, 2, 3>::Map(random_values(rng, 6, 100).data());
  m.a = Eigen::Vector3d::Map(random_values(rng, 3, 1).data());
  return m;
}

TEST(StartWindowCosts, PixelJacobiansInThePoseBlockAndThePoint) {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R_ref = random_rotation(rng);
    const Eigen::Vector2d observed(500, 400);
    const StartPixelCost free_pose(random_model(rng), &R_ref, nullptr, observed, 0.3);
    expect_jacobians_match(free_pose, {random_values(rng, 6, 0.3), random_values(rng, 3, 1)},
                           1e-7);
    const Eigen::Vector3d fixed_t(0.1, -0.2, 0.3);
    const StartPixelCost first_frame(random_model(rng), &R_ref, &fixed_t, observed, 0.3);
    expect_jacobians_match(first_frame, {random_values(rng, 3, 1)}, 1e-7);
  }
}

TEST(StartWindowCosts, MotionJacobiansWithTheSensorsOffset) {
  std::mt19937_64 rng(4);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R0 = random_rotation(rng), R1 = random_rotation(rng);
    MotionPrediction motion;
    motion.cam_from_previous_cam.linear() = random_rotation(rng);
    motion.cam_from_previous_cam.translation() = Eigen::Vector3d::Map(random_values(rng, 3, 0.1).data());
    const Eigen::Matrix<double, 6, 6> B =
        Eigen::Matrix<double, 6, 6>::Map(random_values(rng, 36, 1).data());
    const Eigen::Matrix<double, 6, 6> weight =
        B * B.transpose() + Eigen::Matrix<double, 6, 6>::Identity();
    const Eigen::Matrix<double, 6, 4> C =
        Eigen::Matrix<double, 6, 4>::Map(random_values(rng, 24, 1).data());
    const Eigen::Vector4d offset = Eigen::Vector4d::Map(random_values(rng, 4, 0.01).data());
    const Eigen::Vector3d fixed_t(0.1, 0.2, -0.1);
    for (const MotionPrediction* m : {static_cast<const MotionPrediction*>(&motion), static_cast<const MotionPrediction*>(nullptr)}) {
      const StartMotionCost both_free({&R0, nullptr}, {&R1, nullptr}, m, weight, C, offset);
      expect_jacobians_match(both_free,
                             {random_values(rng, 6, 0.3), random_values(rng, 6, 0.3),
                              random_values(rng, 4, 0.01)},
                             1e-7);
      const StartMotionCost after_first({&R0, &fixed_t}, {&R1, nullptr}, m, weight, C, offset);
      expect_jacobians_match(after_first, {random_values(rng, 6, 0.3), random_values(rng, 4, 0.01)},
                             1e-7);
    }
  }
}

TEST(StartWindowCosts, ScaleHoldJacobian) {
  std::mt19937_64 rng(5);
  const StartScaleCost cost(2.5, 1e-4);
  expect_jacobians_match(cost, {random_values(rng, 6, 1)}, 1e-7);
}

}  // namespace
}  // namespace omnisfm::sfm
