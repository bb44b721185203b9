// The Ceres terms of the smoothed start and of the sliding window: their analytic Jacobians in the
// (w, t) pose blocks and the points' parameters against numeric differentiation, away from w = 0
// where J_left(w) matters.

#include "../src/start_window_costs.h"
#include "../src/window_costs.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <memory>
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

// A pixel smooth in the pose and the point's six parameters with exact Jacobians:
// M (R (A q) + t), whose left-perturbation rotation Jacobian is -M [R A q]x.
PointPixel random_point_model(std::mt19937_64& rng) {
  const Eigen::Matrix<double, 2, 3> M =
      Eigen::Matrix<double, 2, 3>::Map(random_values(rng, 6, 100).data());
  const Eigen::Matrix<double, 3, 6> A =
      Eigen::Matrix<double, 3, 6>::Map(random_values(rng, 18, 1).data());
  return [M, A](const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const PointParams& q,
                bool jacobians, Eigen::Vector2d* pixel, Eigen::Matrix<double, 2, 6>* J_pose,
                Eigen::Matrix<double, 2, 6>* J_point) {
    const Eigen::Vector3d RX = R * (A * q);
    *pixel = M * (RX + t);
    if (jacobians) {
      *J_pose << -M * so3::skew(RX), M;
      *J_point = M * R * A;
    }
    return true;
  };
}

TEST(WindowCosts, PixelJacobiansOfAPointThePriorHolds) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R_ref = random_rotation(rng);
    const std::unique_ptr<WindowPixelCost> cost(
        WindowPixelCost::of_prior_point(random_point_model(rng), &R_ref, {500, 400}, 0.3));
    expect_jacobians_match(*cost, {random_values(rng, 6, 0.3), random_values(rng, 6, 1)}, 1e-7);
  }
}

// A point started in the window: its origin's offset moves with the pose it was started from,
// which is another pose of the window or the one it is seen from.
TEST(WindowCosts, PixelJacobiansOfAPointStartedInTheWindow) {
  std::mt19937_64 rng(12);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R_ref = random_rotation(rng), R_start = random_rotation(rng);
    MovingOrigin origin;
    origin.in_camera = Eigen::Vector3d::Map(random_values(rng, 3, 0.05).data());
    origin.placed = Eigen::Vector3d::Map(random_values(rng, 3, 1).data());
    const std::unique_ptr<WindowPixelCost> from_another(WindowPixelCost::of_started_point(
        random_point_model(rng), &R_ref, &R_start, origin, {500, 400}, 0.3));
    expect_jacobians_match(*from_another,
                           {random_values(rng, 6, 0.3), random_values(rng, 6, 0.3),
                            random_values(rng, 3, 1)},
                           1e-7);
    const std::unique_ptr<WindowPixelCost> from_itself(WindowPixelCost::of_started_point(
        random_point_model(rng), &R_ref, nullptr, origin, {500, 400}, 0.3));
    expect_jacobians_match(*from_itself, {random_values(rng, 6, 0.3), random_values(rng, 3, 1)},
                           1e-7);
  }
}

TEST(WindowCosts, TheJointPriorsJacobiansAreItsWhiteningsColumns) {
  std::mt19937_64 rng(13);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Map(random_values(rng, 15 * 15, 1).data(), 15, 15);
  const Eigen::MatrixXd covariance = B * B.transpose() + Eigen::MatrixXd::Identity(15, 15);
  const Eigen::MatrixXd whitening = Eigen::LLT<Eigen::MatrixXd>(covariance).matrixL().solve(
      Eigen::MatrixXd::Identity(15, 15));
  const Eigen::VectorXd mean = Eigen::VectorXd::Map(random_values(rng, 15, 1).data(), 15);
  const JointPriorCost cost(whitening, mean, {6, 3, 6});
  const std::vector<double> pose = random_values(rng, 6, 1), point3 = random_values(rng, 3, 1),
                            point6 = random_values(rng, 6, 1);
  expect_jacobians_match(cost, {pose, point3, point6}, 1e-7);
  // Its squared norm is the Mahalanobis distance from the mean.
  Eigen::VectorXd x(15);
  x << Eigen::VectorXd::Map(pose.data(), 6), Eigen::VectorXd::Map(point3.data(), 3),
      Eigen::VectorXd::Map(point6.data(), 6);
  const double* blocks[] = {pose.data(), point3.data(), point6.data()};
  Eigen::VectorXd r(15);
  ASSERT_TRUE(cost.Evaluate(blocks, r.data(), nullptr));
  EXPECT_NEAR(r.squaredNorm(), (x - mean).dot(covariance.ldlt().solve(x - mean)),
              1e-9 * r.squaredNorm());
}

// A started point's ray start follows its pose as the filter's new point does: the offset is zero
// at the pose it was placed from, and moves as ray_pose_jacobian's offset rows say.
TEST(WindowCosts, TheMovingOriginIsTheFiltersAnchorOffset) {
  std::mt19937_64 rng(14);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R = random_rotation(rng);
    const Eigen::Vector3d t = Eigen::Vector3d::Map(random_values(rng, 3, 1).data());
    const Eigen::Vector3d origin = Eigen::Vector3d::Map(random_values(rng, 3, 0.05).data());
    const Eigen::Vector3d direction =
        Eigen::Vector3d::Map(random_values(rng, 3, 1).data()).normalized();
    PointAnchor anchor;
    anchor.origin = R.transpose() * (origin - t);
    anchor.basis.col(0) = R.transpose() * direction;
    anchor.basis.col(1) = anchor.basis.col(0).unitOrthogonal();
    anchor.basis.col(2) = anchor.basis.col(0).cross(anchor.basis.col(1));
    MovingOrigin moving;
    moving.in_camera = origin;
    moving.placed = anchor.origin;
    EXPECT_LT(moving.offset(R, t).norm(), 1e-12);
    const Eigen::Matrix<double, 6, 6> G = ray_pose_jacobian(anchor, R, t, origin, direction);
    EXPECT_LT((moving.jacobian(R, t) - G.bottomRows<3>()).norm(), 1e-12 * G.norm());
  }
}

}  // namespace
}  // namespace omnisfm::sfm
