// The motion residuals' and the filter's motion prediction's analytic Jacobians against central
// differences, and the gyro integration's bias Jacobian against re-integration.

#include "omnisfm/sfm/motion_residuals.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "jacobian_check.h"
#include "omnisfm/sfm/motion_prediction.h"

namespace omnisfm::sfm {
namespace {

// A camera on a vehicle, turned and offset as real mounts are.
Eigen::Isometry3d body_from_cam() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(3.0, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  T.translation() << 0.3, -0.1, 0.8;
  return T;
}

Eigen::Matrix<double, 6, 1> random_pose(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0, 1);
  Eigen::Matrix<double, 6, 1> p;
  for (int i = 0; i < 6; ++i) p[i] = n(rng);
  return p;
}

std::vector<double> as_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// A pose near another: the vehicle's motion between two frames.
Eigen::Matrix<double, 6, 1> nearby(const Eigen::Matrix<double, 6, 1>& p, std::mt19937_64& rng) {
  return p + 0.1 * random_pose(rng);
}

TEST(MotionResiduals, OdometryJacobians) {
  std::mt19937_64 rng(1);
  OdometryIncrement increment;
  increment.delta << 0.12, -0.03, 0.2;
  increment.covariance = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  increment.covariance(0, 1) = increment.covariance(1, 0) = 5e-5;
  std::unique_ptr<ceres::CostFunction> cost(make_odometry_cost(increment, body_from_cam()));
  for (int trial = 0; trial < 5; ++trial) {
    const auto a = random_pose(rng);
    expect_jacobians_match(*cost, {as_vector(a), as_vector(nearby(a, rng)), {1.02}}, 1e-6);
  }
}

// The residual is in what the wheel read, so the same drive in other units (the scene, the mount's
// offset and the wheel's scale all times c) has the same residual. Were it in metres it would
// shrink with the scene, and the batch would shrink the scene to lower it.
TEST(MotionResiduals, OdometryResidualDoesNotChangeWithTheSceneUnits) {
  std::mt19937_64 rng(4);
  OdometryIncrement increment;
  increment.delta << 0.12, -0.03, 0.2;
  increment.covariance = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  const auto a = random_pose(rng), b = nearby(a, rng);
  const double scale = 1.02;
  const auto residual = [&](double c) {
    Eigen::Isometry3d mount = body_from_cam();
    mount.translation() *= c;
    std::unique_ptr<ceres::CostFunction> cost(make_odometry_cost(increment, mount));
    Eigen::Matrix<double, 6, 1> a_c = a, b_c = b;
    a_c.tail<3>() *= c;
    b_c.tail<3>() *= c;
    const double scale_c = c * scale;
    const double* blocks[] = {a_c.data(), b_c.data(), &scale_c};
    Eigen::Vector3d r;
    cost->Evaluate(blocks, r.data(), nullptr);
    return r;
  };
  const Eigen::Vector3d reference = residual(1);
  ASSERT_GT(reference.head<2>().norm(), 1.0) << "a drive that disagrees with the wheel";
  for (double c : {0.5, 3.0}) EXPECT_LT((residual(c) - reference).norm(), 1e-9 * reference.norm());
}

TEST(MotionResiduals, GyroJacobians) {
  std::mt19937_64 rng(2);
  GyroIncrement increment;
  increment.valid = true;
  increment.dt = 0.5;
  increment.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  increment.bias_lin << 1e-3, -2e-3, 3e-3;
  increment.J_rotation_bias = -0.5 * Eigen::Matrix3d::Identity();
  increment.J_rotation_bias(0, 1) = 0.05;
  increment.covariance = 2e-8 * Eigen::Matrix3d::Identity();
  std::unique_ptr<ceres::CostFunction> cost(make_gyro_cost(increment, body_from_cam()));
  for (int trial = 0; trial < 5; ++trial) {
    const auto a = random_pose(rng);
    expect_jacobians_match(*cost, {as_vector(a), as_vector(nearby(a, rng)), {0.02, -0.01, 0.005}},
                           1e-6);
  }
}

TEST(MotionResiduals, GpsJacobians) {
  std::mt19937_64 rng(3);
  const Eigen::Matrix3d covariance = Eigen::Vector3d(4e-4, 4e-4, 1.6e-3).asDiagonal();
  for (double alpha : {0.0, 0.3, 1.0}) {
    std::unique_ptr<ceres::CostFunction> cost(
        make_gps_cost(Eigen::Vector3d(1, 2, 3), covariance, alpha, Eigen::Vector3d(0.1, 0.2, -0.3)));
    const auto a = random_pose(rng);
    expect_jacobians_match(*cost, {as_vector(a), as_vector(nearby(a, rng))}, 1e-6);
  }
}

// The camera motion's covariance comes from J_camera_body, the first-order map of the body
// motion's error (right-perturbed rotation, translation) to the camera motion's (left-perturbed
// rotation, translation). Recovered here column by column from central differences.
TEST(MotionPrediction, CameraCovarianceFollowsTheBodyMotion) {
  BodyMotion body;
  body.previous_body_from_body.linear() =
      Eigen::AngleAxisd(0.2, Eigen::Vector3d(0.1, 0.2, 1).normalized()).toRotationMatrix();
  body.previous_body_from_body.translation() << 0.2, 0.05, 0.01;
  const Eigen::Isometry3d mount = body_from_cam();
  const MotionPrediction mean = predict_camera_motion(body, mount);
  Eigen::Matrix<double, 6, 6> J;
  const double h = 1e-6;
  for (int j = 0; j < 6; ++j) {
    Eigen::Matrix<double, 6, 1> e = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 6, 1> difference = Eigen::Matrix<double, 6, 1>::Zero();
    for (double sign : {1.0, -1.0}) {
      e[j] = sign * h;
      BodyMotion moved = body;
      moved.previous_body_from_body.linear() =
          body.previous_body_from_body.linear() *
          Eigen::AngleAxisd(e.head<3>().norm(), e.head<3>().normalized()).toRotationMatrix();
      moved.previous_body_from_body.translation() += e.tail<3>();
      const Eigen::Isometry3d M = predict_camera_motion(moved, mount).cam_from_previous_cam;
      const Eigen::AngleAxisd left(M.linear() * mean.cam_from_previous_cam.linear().transpose());
      Eigen::Matrix<double, 6, 1> error;
      error << left.angle() * left.axis(), M.translation() - mean.cam_from_previous_cam.translation();
      difference = sign > 0 ? error : Eigen::Matrix<double, 6, 1>(difference - error);
    }
    J.col(j) = difference / (2 * h);
  }
  Eigen::Matrix<double, 6, 6> body_covariance = Eigen::Matrix<double, 6, 6>::Zero();
  body_covariance.diagonal() << 1, 2, 3, 4, 5, 6;
  body_covariance(0, 4) = body_covariance(4, 0) = 0.5;
  body.covariance = body_covariance;
  const Eigen::Matrix<double, 6, 6> expected = J * body_covariance * J.transpose();
  EXPECT_LT((predict_camera_motion(body, mount).covariance - expected).cwiseAbs().maxCoeff(),
            1e-6 * expected.cwiseAbs().maxCoeff());
}

// The prediction's dependence on the sensors' states the filter estimates: the camera motion at
// bias b + db is Exp(B db) M(b) (left-perturbed rotation, then translation), B against central
// differences through the whole prediction (the gyro integrated again at each bias); the same for
// the wheels' scale correction.
TEST(MotionPrediction, SensorStateJacobiansMatchCentralDifferences) {
  MotionSensors sensors;
  sensors.body_from_cam = body_from_cam();
  const Eigen::Vector3d rate(0.1, -0.05, 0.3);
  for (int i = 0; i <= 60; ++i) {
    const double t = 0.01 * i;
    sensors.gyro.push_back({t, rate + Eigen::Vector3d(0.01 * std::sin(7 * t), 0, 0.02 * t)});
    sensors.odometry.push_back({t, Eigen::Vector3d(0.3 * t, 0.02 * t * t, 0.3 * t)});
  }
  const FilterSettings settings;
  const Eigen::Vector3d bias(0.004, -0.002, 0.003);
  SensorStates states;
  states.gyro_bias = bias;
  const MotionPrediction at = predict_camera_motion(sensors, 0.05, 0.55, settings, states);
  ASSERT_GT(at.bias_jacobian.norm(), 0.1);
  EXPECT_NEAR(at.bias_walk_variance,
              std::pow(sensors.gyro_noise.bias_walk, 2) * 0.5, 1e-15);
  EXPECT_EQ(at.bias_prior_variance, std::pow(sensors.gyro_noise.bias_sigma, 2));
  const double h = 1e-5;
  Eigen::Matrix<double, 6, 3> numeric;
  for (int j = 0; j < 3; ++j) {
    Eigen::Matrix<double, 6, 1> difference = Eigen::Matrix<double, 6, 1>::Zero();
    for (double sign : {1.0, -1.0}) {
      SensorStates moved = states;
      moved.gyro_bias += sign * h * Eigen::Vector3d::Unit(j);
      const Eigen::Isometry3d M =
          predict_camera_motion(sensors, 0.05, 0.55, settings, moved).cam_from_previous_cam;
      const Eigen::AngleAxisd left(M.linear() * at.cam_from_previous_cam.linear().transpose());
      Eigen::Matrix<double, 6, 1> error;
      error << left.angle() * left.axis(), M.translation() - at.cam_from_previous_cam.translation();
      difference += sign * error;
    }
    numeric.col(j) = difference / (2 * h);
  }
  EXPECT_LT((at.bias_jacobian - numeric).cwiseAbs().maxCoeff(), 1e-6 * numeric.norm())
      << at.bias_jacobian << "\n\n" << numeric;
  // The wheels' scale correction the same way.
  FilterSettings with_scale = settings;
  with_scale.estimate_wheel_scale = true;
  sensors.odometry_scale = 0.98;
  states.wheel_scale = 1.01;
  const MotionPrediction scaled = predict_camera_motion(sensors, 0.05, 0.55, with_scale, states);
  ASSERT_GT(scaled.wheel_scale_jacobian.norm(), 0.1);
  EXPECT_EQ(scaled.wheel_scale_prior_variance, std::pow(sensors.odometry_noise.scale_sigma, 2));
  Eigen::Matrix<double, 6, 1> scale_difference = Eigen::Matrix<double, 6, 1>::Zero();
  for (double sign : {1.0, -1.0}) {
    SensorStates moved = states;
    moved.wheel_scale += sign * h;
    const Eigen::Isometry3d M =
        predict_camera_motion(sensors, 0.05, 0.55, with_scale, moved).cam_from_previous_cam;
    const Eigen::AngleAxisd left(M.linear() * scaled.cam_from_previous_cam.linear().transpose());
    Eigen::Matrix<double, 6, 1> error;
    error << left.angle() * left.axis(),
        M.translation() - scaled.cam_from_previous_cam.translation();
    scale_difference += sign * error;
  }
  EXPECT_LT((scaled.wheel_scale_jacobian - scale_difference / (2 * h)).cwiseAbs().maxCoeff(),
            1e-6 * scaled.wheel_scale_jacobian.norm());
  FilterSettings calibrated = settings;
  calibrated.estimate_wheel_scale = false;
  EXPECT_TRUE(predict_camera_motion(sensors, 0.05, 0.55, calibrated, states)
                  .wheel_scale_jacobian.isZero());
  // With the bias not estimated, it is the prediction's noise instead.
  FilterSettings folded = settings;
  folded.estimate_gyro_bias = false;
  const MotionPrediction inflated = predict_camera_motion(sensors, 0.05, 0.55, folded, states);
  EXPECT_TRUE(inflated.bias_jacobian.isZero());
  const double rotation_variance = inflated.covariance.topLeftCorner(3, 3).trace() -
                                   at.covariance.topLeftCorner(3, 3).trace();
  EXPECT_GT(rotation_variance, 0.9 * 3 * std::pow(0.5 * sensors.gyro_noise.bias_sigma, 2));
}

// The wheel's scale multiplies the distances read and their standard deviations.
TEST(MotionPrediction, OdometryScaleScalesTheTranslationAndItsNoise) {
  FrameMotion motion;
  motion.odometry.valid = true;
  motion.odometry.delta << 0.3, 0.02, 0.1;
  motion.odometry.covariance = Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal();
  MotionSensors sensors;  // the camera is the body
  const FilterSettings settings;
  const MotionPrediction one = predict_camera_motion(motion, sensors, settings);
  sensors.odometry_scale = 2;
  const MotionPrediction two = predict_camera_motion(motion, sensors, settings);
  EXPECT_LT((two.cam_from_previous_cam.translation() - 2 * one.cam_from_previous_cam.translation())
                .norm(),
            1e-12);
  EXPECT_LT((two.covariance.block<2, 2>(3, 3) - 4 * one.covariance.block<2, 2>(3, 3))
                .cwiseAbs()
                .maxCoeff(),
            1e-15);
  const Eigen::Matrix3d rotation_one = one.covariance.topLeftCorner<3, 3>();
  const Eigen::Matrix3d rotation_two = two.covariance.topLeftCorner<3, 3>();
  EXPECT_EQ(rotation_two, rotation_one);
}

std::vector<GyroSample> turning_gyro() {
  std::vector<GyroSample> gyro;
  for (int i = 0; i <= 200; ++i) {
    const double t = 0.01 * i;
    gyro.push_back({t, Eigen::Vector3d(0.3 * std::sin(t), 0.2, 0.5 * std::cos(3 * t))});
  }
  return gyro;
}

TEST(FrameMotion, GyroBiasJacobian) {
  const auto gyro = turning_gyro();
  const GyroNoise noise;
  const Eigen::Vector3d bias(0.01, -0.02, 0.005);
  const GyroIncrement at = integrate_gyro(gyro, noise, 0.333, 1.5, bias);
  ASSERT_TRUE(at.valid);
  const double h = 1e-6;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d d = h * Eigen::Vector3d::Unit(j);
    const Eigen::Matrix3d plus = integrate_gyro(gyro, noise, 0.333, 1.5, bias + d).rotation;
    const Eigen::Matrix3d minus = integrate_gyro(gyro, noise, 0.333, 1.5, bias - d).rotation;
    const Eigen::AngleAxisd change(minus.transpose() * plus);
    const Eigen::Vector3d column = change.angle() * change.axis() / (2 * h);
    EXPECT_LT((column - at.J_rotation_bias.col(j)).norm(), 1e-6) << "column " << j;
  }
  // White rate noise over 1.167 s: about noise_density^2 * dt per axis.
  EXPECT_NEAR(at.covariance.trace() / 3, noise.noise_density * noise.noise_density * 1.167, 1e-10);
}

TEST(FrameMotion, OdometryIsInterpolatedAtFrameTimes) {
  std::vector<OdometrySample> odometry;
  // Driving a circle of radius 2 m at 0.5 rad/s, read at 10 Hz.
  for (int i = 0; i <= 30; ++i) {
    const double t = 0.1 * i, yaw = 0.5 * t;
    odometry.push_back({t, Eigen::Vector3d(2 * std::sin(yaw), 2 - 2 * std::cos(yaw), yaw)});
  }
  OdometryNoise noise;
  const OdometryIncrement increment = odometry_increment(odometry, noise, 0.5, 2.5);
  ASSERT_TRUE(increment.valid);
  const double turn = 0.5 * 2.0;  // yaw change over the 2 s
  // The chord of the arc, seen from its start; within the error of interpolating inside 0.1 s.
  EXPECT_NEAR(increment.delta.z(), turn, 1e-12);
  EXPECT_NEAR(increment.delta.x(), 2 * std::sin(turn), 1e-3);
  EXPECT_NEAR(increment.delta.y(), 2 - 2 * std::cos(turn), 1e-3);
  EXPECT_NEAR(increment.covariance(0, 0), 1e-4 * increment.distance, 1e-12);
  EXPECT_FALSE(odometry_increment(odometry, noise, 2.9, 3.2).valid) << "beyond the readings";
}

}  // namespace
}  // namespace omnisfm::sfm
