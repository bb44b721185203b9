#pragma once
// The online filter's propagation from the vehicle's sensors: the motion between two frames that
// the odometry and the gyro measured (frame_motion.h), with its covariance, as the camera's
// motion the filter takes (MotionPrediction).
//
// The rotation comes from the gyro when there is one (integrated at the filter's bias estimate,
// with its noise; with FilterSettings::estimate_gyro_bias off, the bias prior over the interval
// added to that noise instead), else from the odometry's yaw; the translation
// from the odometry (planar: x, y in the earlier body frame). Whatever no sensor measures (the
// translation with a gyro alone, roll and pitch with odometry alone, the height) keeps the
// filter's random walk.

#include <Eigen/Geometry>

#include "omnisfm/sfm/frame_motion.h"
#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/online_filter.h"

namespace omnisfm::sfm {

// previous_body_from_body with the covariance of its error: rotation as a right perturbation
// (R = R_mean Exp(e_r)), then translation (p = p_mean + e_p).
// With the bias estimated: the error's dependence on the bias's error, and the bias's walk over
// the interval and prior, per axis (as MotionPrediction's).
struct BodyMotion {
  Eigen::Isometry3d previous_body_from_body = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 3> bias_jacobian = Eigen::Matrix<double, 6, 3>::Zero();
  double bias_walk_variance = 0;
  double bias_prior_variance = 0;
  Eigen::Matrix<double, 6, 1> wheel_scale_jacobian = Eigen::Matrix<double, 6, 1>::Zero();
  double wheel_scale_prior_variance = 0;
  bool measures_distance = false;  // the odometry measured it (MotionPrediction's)
};

BodyMotion predict_body_motion(const FrameMotion& motion, const GyroNoise& gyro_noise,
                               const FilterSettings& settings);

// The same motion seen by the camera mounted at body_from_cam, in the filter's terms.
MotionPrediction predict_camera_motion(const BodyMotion& body, const Eigen::Isometry3d& body_from_cam);

// What the filter takes for the frame interval `motion`: the body's motion with the odometry's
// distances times sensors.odometry_scale and the filter's wheel_scale, seen by the camera at
// sensors.body_from_cam (the gyro's bias is the one `motion` was integrated at).
MotionPrediction predict_camera_motion(const FrameMotion& motion, const MotionSensors& sensors,
                                       const FilterSettings& settings, double wheel_scale = 1);

// The same between two frame times, for a filter fed live (the readings up to t1 must be in), at
// the filter's estimates of the sensors (OnlineFilter::sensor_states()).
MotionPrediction predict_camera_motion(const MotionSensors& sensors, double t0, double t1,
                                       const FilterSettings& settings,
                                       const SensorStates& states = SensorStates());

// How many axes of the rotation `prediction` measures (the odometry's yaw: 1; a gyro: 3), where
// the rest keep the walk's sigma: its rotation covariance's eigenvalues, whichever way the camera
// is mounted, well below the walk's variance (rotation_walk_sigma squared).
int measured_rotation_axes(const MotionPrediction& prediction, double rotation_walk_sigma);

// Whether `prediction` measures the whole motion: all three axes of the rotation and the distance.
bool measures_whole_motion(const MotionPrediction& prediction, double rotation_walk_sigma);

}  // namespace omnisfm::sfm
