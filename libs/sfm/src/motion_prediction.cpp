#include "omnisfm/sfm/motion_prediction.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "so3.h"

namespace omnisfm::sfm {

BodyMotion predict_body_motion(const FrameMotion& motion, const GyroNoise& gyro_noise,
                               const FilterSettings& settings) {
  BodyMotion body;
  const double rotation_walk = settings.rotation_walk_sigma * settings.rotation_walk_sigma;
  const double translation_walk = settings.translation_walk_sigma * settings.translation_walk_sigma;
  body.covariance.diagonal() << Eigen::Vector3d::Constant(rotation_walk),
      Eigen::Vector3d::Constant(translation_walk);
  if (motion.gyro.valid) {
    body.previous_body_from_body.linear() = motion.gyro.rotation;
    body.covariance.topLeftCorner<3, 3>() = motion.gyro.covariance;
    if (settings.estimate_gyro_bias) {
      body.bias_jacobian.topRows<3>() = motion.gyro.J_rotation_bias;
      body.bias_walk_variance = gyro_noise.bias_walk * gyro_noise.bias_walk * motion.gyro.dt;
      body.bias_prior_variance = gyro_noise.bias_sigma * gyro_noise.bias_sigma;
    } else {
      const double bias = gyro_noise.bias_sigma * motion.gyro.dt;
      body.covariance.topLeftCorner<3, 3>() += bias * bias * Eigen::Matrix3d::Identity();
    }
  } else if (motion.odometry.valid) {
    body.previous_body_from_body.linear() =
        Eigen::AngleAxisd(motion.odometry.delta.z(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    body.covariance(2, 2) = motion.odometry.covariance(2, 2);
  }
  if (motion.odometry.valid) {
    body.previous_body_from_body.translation() << motion.odometry.delta.head<2>(), 0;
    body.covariance.block<2, 2>(3, 3) = motion.odometry.covariance.topLeftCorner<2, 2>();
  }
  return body;
}

// M = cam_from_body D^-1 body_from_cam, with D = previous_body_from_body:
//   R_M = R_cb D_R^T R_bc,  t_M = R_cb D_R^T (p_bc - D_p) + p_cb.
// With D_R = D_R Exp(e_r) and D_p + e_p, to first order, for M's left-perturbed error:
//   dm = -R_cb e_r,   dt_M = R_cb [D_R^T (p_bc - D_p)]x e_r - R_cb D_R^T e_p.
MotionPrediction predict_camera_motion(const BodyMotion& body,
                                       const Eigen::Isometry3d& body_from_cam) {
  const Eigen::Isometry3d cam_from_body = body_from_cam.inverse();
  const Eigen::Isometry3d& D = body.previous_body_from_body;
  MotionPrediction camera;
  camera.cam_from_previous_cam = cam_from_body * D.inverse() * body_from_cam;
  const Eigen::Matrix3d R_cb = cam_from_body.linear();
  const Eigen::Vector3d v = D.linear().transpose() * (body_from_cam.translation() - D.translation());
  Eigen::Matrix<double, 6, 6> J = Eigen::Matrix<double, 6, 6>::Zero();
  J.topLeftCorner<3, 3>() = -R_cb;
  J.bottomLeftCorner<3, 3>() = R_cb * so3::skew(v);
  J.bottomRightCorner<3, 3>() = -R_cb * D.linear().transpose();
  camera.covariance = J * body.covariance * J.transpose();
  camera.bias_jacobian = J * body.bias_jacobian;
  camera.bias_walk_variance = body.bias_walk_variance;
  camera.bias_prior_variance = body.bias_prior_variance;
  camera.wheel_scale_jacobian = J * body.wheel_scale_jacobian;
  camera.wheel_scale_prior_variance = body.wheel_scale_prior_variance;
  camera.measures_distance = body.measures_distance;
  return camera;
}

MotionPrediction predict_camera_motion(const FrameMotion& motion, const MotionSensors& sensors,
                                       const FilterSettings& settings, double wheel_scale) {
  BodyMotion body = predict_body_motion(motion, sensors.gyro_noise, settings);
  if (motion.odometry.valid) {
    body.measures_distance = true;
    // Distances read times the scale; their noise with them.
    const double s = sensors.odometry_scale * wheel_scale;
    body.previous_body_from_body.translation() *= s;
    body.covariance.block<2, 2>(3, 3) *= s * s;
    if (settings.estimate_wheel_scale) {
      // The translation per unit of the correction: what the calibrated wheels read.
      body.wheel_scale_jacobian.segment<3>(3) =
          body.previous_body_from_body.translation() / wheel_scale;
      body.wheel_scale_prior_variance = std::pow(sensors.odometry_noise.scale_sigma, 2);
    }
  }
  return predict_camera_motion(body, sensors.body_from_cam);
}

MotionPrediction predict_camera_motion(const MotionSensors& sensors, double t0, double t1,
                                       const FilterSettings& settings,
                                       const SensorStates& states) {
  return predict_camera_motion(frame_motion(sensors, t0, t1, states.gyro_bias), sensors, settings,
                               states.wheel_scale);
}

int measured_rotation_axes(const MotionPrediction& prediction, double rotation_walk_sigma) {
  const Eigen::Vector3d variances =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(prediction.covariance.topLeftCorner<3, 3>(),
                                                     Eigen::EigenvaluesOnly)
          .eigenvalues();
  const double walk_variance = rotation_walk_sigma * rotation_walk_sigma;
  return static_cast<int>((variances.array() < 0.25 * walk_variance).count());
}

bool measures_whole_motion(const MotionPrediction& prediction, double rotation_walk_sigma) {
  return prediction.measures_distance &&
         measured_rotation_axes(prediction, rotation_walk_sigma) == 3;
}

}  // namespace omnisfm::sfm
