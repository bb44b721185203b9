// The smoothed start's motion prior: its analytic Jacobians against central differences in the
// filter's chart (R = Exp(dtheta) R, t = t + dt).

#include "../src/motion_prior_residual.h"

#include <gtest/gtest.h>

#include <random>

namespace omnisfm::sfm {
namespace {

struct Pose {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
};

Pose perturbed(const Pose& p, const Eigen::Matrix<double, 6, 1>& d) {
  return {so3::exp(d.head<3>()) * p.R, p.t + d.tail<3>()};
}

void expect_jacobians_match(const Pose& previous, const Pose& current,
                            const MotionPrediction* motion) {
  const MotionPriorResidual r =
      motion_prior_residual(previous.R, previous.t, current.R, current.t, motion);
  const double h = 1e-6;
  for (int j = 0; j < 6; ++j) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    d[j] = h;
    const Pose p_plus = perturbed(previous, d), p_minus = perturbed(previous, -d);
    const Pose c_plus = perturbed(current, d), c_minus = perturbed(current, -d);
    const Eigen::Matrix<double, 6, 1> numeric_previous =
        (motion_prior_residual(p_plus.R, p_plus.t, current.R, current.t, motion).e -
         motion_prior_residual(p_minus.R, p_minus.t, current.R, current.t, motion).e) / (2 * h);
    const Eigen::Matrix<double, 6, 1> numeric_current =
        (motion_prior_residual(previous.R, previous.t, c_plus.R, c_plus.t, motion).e -
         motion_prior_residual(previous.R, previous.t, c_minus.R, c_minus.t, motion).e) / (2 * h);
    EXPECT_LT((numeric_previous - r.J_previous.col(j)).cwiseAbs().maxCoeff(), 1e-7) << "column " << j;
    EXPECT_LT((numeric_current - r.J_current.col(j)).cwiseAbs().maxCoeff(), 1e-7) << "column " << j;
  }
}

Pose random_pose(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  const Eigen::Vector3d w(n(rng), n(rng), n(rng)), t(n(rng), n(rng), n(rng));
  return {so3::exp(w), t};
}

// The next pose: the previous moved by a few degrees and decimetres, off the prediction.
Pose moved(const Pose& p, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 0.1);
  return {so3::exp(Eigen::Vector3d(n(rng), n(rng), n(rng))) * p.R,
          p.t + Eigen::Vector3d(n(rng), n(rng), n(rng))};
}

TEST(MotionPriorResidual, RandomWalkJacobians) {
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 5; ++trial) {
    const Pose previous = random_pose(rng);
    expect_jacobians_match(previous, moved(previous, rng), nullptr);
  }
}

TEST(MotionPriorResidual, PredictedMotionJacobians) {
  std::mt19937_64 rng(6);
  for (int trial = 0; trial < 5; ++trial) {
    MotionPrediction motion;
    const Pose m = random_pose(rng);
    motion.cam_from_previous_cam.linear() = m.R;
    motion.cam_from_previous_cam.translation() = 0.3 * m.t;
    const Pose previous = random_pose(rng);
    // The current pose near the predicted one.
    const Pose predicted{m.R * previous.R, m.R * previous.t + 0.3 * m.t};
    expect_jacobians_match(previous, moved(predicted, rng), &motion);
  }
}

TEST(MotionPriorResidual, ZeroWhenThePoseMovedAsPredicted) {
  std::mt19937_64 rng(7);
  MotionPrediction motion;
  const Pose m = random_pose(rng);
  motion.cam_from_previous_cam.linear() = m.R;
  motion.cam_from_previous_cam.translation() = m.t;
  const Pose previous = random_pose(rng);
  const MotionPriorResidual r = motion_prior_residual(
      previous.R, previous.t, m.R * previous.R, m.R * previous.t + m.t, &motion);
  EXPECT_LT(r.e.cwiseAbs().maxCoeff(), 1e-12);
  const MotionPriorResidual still =
      motion_prior_residual(previous.R, previous.t, previous.R, previous.t, nullptr);
  EXPECT_LT(still.e.cwiseAbs().maxCoeff(), 1e-12);
}

}  // namespace
}  // namespace omnisfm::sfm
