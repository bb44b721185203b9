// The batch's reprojection residual: its analytic Jacobians against Ceres' numeric ones.

#include <gtest/gtest.h>

#include <random>

#include "../src/camera_refinement.h"
#include "../src/projection_cost.h"
#include "jacobian_check.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {
namespace {

struct Observation {
  std::vector<double> pose, point;  // cam_from_world (angle-axis, translation), world point
  Eigen::Vector2d pixel;
};

// Rover-like views: the rig turned and moved, points 0.5-8 m away around it and below the
// horizon, each observed 0.5 px off its projection.
std::vector<Observation> observations(const camera::CatadioptricCamera& camera, int count) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Observation> out;
  while (static_cast<int>(out.size()) < count) {
    Observation o;
    o.pose = {0.3 * u(rng), 0.3 * u(rng), 3 * u(rng), u(rng), u(rng), 0.5 * u(rng)};
    const double azimuth = 3.2 * u(rng), distance = 4.25 + 3.75 * u(rng);
    const Eigen::Vector3d X_C(distance * std::cos(azimuth), distance * std::sin(azimuth),
                              -0.6 + 0.5 * u(rng));
    // The world point whose camera-frame position is X_C.
    double rotated[3];
    const double inverse_rotation[3] = {-o.pose[0], -o.pose[1], -o.pose[2]};
    const double shifted[3] = {X_C.x() - o.pose[3], X_C.y() - o.pose[4], X_C.z() - o.pose[5]};
    ceres::AngleAxisRotatePoint(inverse_rotation, shifted, rotated);
    o.point.assign(rotated, rotated + 3);
    if (!camera.project(X_C, &o.pixel)) continue;
    o.pixel += Eigen::Vector2d(0.5, -0.5);
    out.push_back(o);
  }
  return out;
}

// Relative, per entry: the mirror solve stops within about 1e-11 px, which numeric
// differentiation's small steps turn into errors of up to some 1e-5 of an entry.
constexpr double kDerivativeTolerance = 1e-5;

TEST(ProjectionCost, JacobiansMatchNumericDerivatives) {
  const camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  for (const Observation& o : observations(camera, 50)) {
    ProjectionCost cost(&camera, o.pixel);
    expect_jacobians_match(cost, {o.pose, o.point}, kDerivativeTolerance);
  }
}

TEST(ScaledProjectionCost, JacobiansMatchNumericDerivatives) {
  const camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  for (const Observation& o : observations(camera, 50)) {
    // The same camera-frame point with the scene 1.3x larger and u = 1.3.
    Observation scaled = o;
    for (int k = 3; k < 6; ++k) scaled.pose[k] *= 1.3;
    for (double& x : scaled.point) x *= 1.3;
    ScaledProjectionCost cost(&camera, o.pixel);
    expect_jacobians_match(cost, {scaled.pose, scaled.point, {1.3}}, kDerivativeTolerance);
    // And the residual is the unscaled one's.
    ProjectionCost plain(&camera, o.pixel);
    double r_plain[2], r_scaled[2];
    const double u = 1.3;
    const double* plain_blocks[] = {o.pose.data(), o.point.data()};
    const double* scaled_blocks[] = {scaled.pose.data(), scaled.point.data(), &u};
    ASSERT_TRUE(plain.Evaluate(plain_blocks, r_plain, nullptr));
    ASSERT_TRUE(cost.Evaluate(scaled_blocks, r_scaled, nullptr));
    EXPECT_NEAR(r_scaled[0], r_plain[0], 1e-9);
    EXPECT_NEAR(r_scaled[1], r_plain[1], 1e-9);
  }
}

// A cost on the problem's shared camera, the camera moved to its block's values before each
// evaluation as the problem's evaluation callback does (GradientChecker calls none).
class WithSharedCamera : public ceres::CostFunction {
 public:
  WithSharedCamera(const camera::CatadioptricCamera& camera, const Eigen::Vector2d& pixel)
      : block_(camera.params()), shared_(camera, block_.data()), cost_(&shared_, pixel) {
    set_num_residuals(2);
    *mutable_parameter_block_sizes() = cost_.parameter_block_sizes();
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    block_ = Eigen::Map<const Eigen::VectorXd>(parameters[3], block_.size());
    shared_.PrepareForEvaluation(jacobians != nullptr, true);
    return cost_.Evaluate(parameters, residuals, jacobians);
  }

 private:
  mutable Eigen::VectorXd block_;
  mutable camera::SharedCamera shared_;
  RefinedProjectionCost cost_;
};

TEST(RefinedProjectionCost, JacobiansMatchNumericDerivativesCameraIncluded) {
  const camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  const Eigen::VectorXd params = camera.params();
  const std::vector<double> camera_block(params.data(), params.data() + params.size());
  for (const Observation& o : observations(camera, 20)) {
    WithSharedCamera cost(camera, o.pixel);
    expect_jacobians_match(cost, {o.pose, o.point, {1.0}, camera_block}, kDerivativeTolerance);
    // At the camera's own parameters, the residual is the fixed camera's.
    ScaledProjectionCost fixed(&camera, o.pixel);
    double r_refined[2], r_fixed[2];
    const double u = 1;
    const double* refined_blocks[] = {o.pose.data(), o.point.data(), &u, camera_block.data()};
    const double* fixed_blocks[] = {o.pose.data(), o.point.data(), &u};
    ASSERT_TRUE(cost.Evaluate(refined_blocks, r_refined, nullptr));
    ASSERT_TRUE(fixed.Evaluate(fixed_blocks, r_fixed, nullptr));
    EXPECT_EQ(r_refined[0], r_fixed[0]);
    EXPECT_EQ(r_refined[1], r_fixed[1]);
  }
}

TEST(CameraPriorCost, WhitensTheListedParametersByTheirCovariance) {
  // Parameters 1 and 3 of four, sigmas 2 and 3, correlation 0.5, in units of weight 0.1.
  const Eigen::Vector4d calibrated(10, 20, 30, 40);
  Eigen::Matrix2d covariance;
  covariance << 4, 3, 3, 9;
  CameraPriorCost cost(calibrated, {1, 3}, covariance, 0.1);
  const std::vector<double> moved = {11, 22, 33, 37};
  const double* blocks[] = {moved.data()};
  double r[2];
  ASSERT_TRUE(cost.Evaluate(blocks, r, nullptr));
  // |r|^2 is 0.01 times the Mahalanobis distance of (2, -3) under the covariance.
  const Eigen::Vector2d step(2, -3);
  EXPECT_NEAR(r[0] * r[0] + r[1] * r[1], 0.01 * step.dot(covariance.inverse() * step), 1e-12);
  EXPECT_NEAR(r[0], 0.1 * 2 / 2, 1e-12);  // the first listed: its own sigma
  expect_jacobians_match(cost, {moved}, 1e-9);
}

}  // namespace
}  // namespace omnisfm::sfm
