#pragma once
// The vehicle's sensors summed up between consecutive image frames: what the odometry and the
// gyro say about how the body moved from frame k to frame k+1, with the covariance of that
// from their noise models. Both the online filter's propagation and the batch's relative-motion
// residuals start from these.
//
// Odometry is interpolated at the frame times (linear in x, y and in the wrapped yaw between the
// readings around each), and the increment is the later pose relative to the earlier one, in the
// earlier body frame. Its covariance grows with the distance d it covers, as a wheel's error does:
// diag(position_sigma^2, position_sigma^2, heading_sigma^2) * max(d, 1 mm).
//
// The gyro's rates are held from each sample to the next, and integrated with a bias b_lin taken
// away: dR = prod Exp((w_i - b_lin) dt_i), body_k_from_body_k+1. A bias b near b_lin changes it to
// first order as dR(b) = dR Exp(J_rotation_bias (b - b_lin)). The covariance of the rotation error
// (a right perturbation) is that of white rate noise, about noise_density^2 * dt per axis.

#include <Eigen/Geometry>
#include <vector>

#include "omnisfm/sfm/motion_sensors.h"

namespace omnisfm::sfm {

struct OdometryIncrement {
  bool valid = false;                  // both frame times lie within the odometry's readings
  Eigen::Vector3d delta{0, 0, 0};      // dx, dy (m, earlier body frame), dyaw (rad)
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  double distance = 0;                 // |dx, dy|
};

struct GyroIncrement {
  bool valid = false;  // both frame times lie within the gyro's samples
  double dt = 0;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // body_k_from_body_k+1 at bias_lin
  Eigen::Vector3d bias_lin{0, 0, 0};
  Eigen::Matrix3d J_rotation_bias = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // of the rotation vector error
};

// Between frame k and k+1.
struct FrameMotion {
  OdometryIncrement odometry;
  GyroIncrement gyro;
};

// The odometry pose (x, y, yaw) at time t, interpolated; false outside the readings.
bool interpolate_odometry(const std::vector<OdometrySample>& odometry, double t,
                          Eigen::Vector3d* pose);

OdometryIncrement odometry_increment(const std::vector<OdometrySample>& odometry,
                                     const OdometryNoise& noise, double t0, double t1);

GyroIncrement integrate_gyro(const std::vector<GyroSample>& gyro, const GyroNoise& noise,
                             double t0, double t1, const Eigen::Vector3d& bias_lin);

// The odometry increment and the integrated gyro between t0 and t1 (either invalid where its
// sensor does not cover the interval).
FrameMotion frame_motion(const MotionSensors& sensors, double t0, double t1,
                         const Eigen::Vector3d& gyro_bias_lin);

// One per pair of consecutive frames (frame_timestamps.size() - 1 of them).
std::vector<FrameMotion> frame_motions(const MotionSensors& sensors,
                                       const std::vector<double>& frame_timestamps,
                                       const Eigen::Vector3d& gyro_bias_lin);

// Planar poses: a (+) b, and b relative to a (the b' with a (+) b' = b); yaw wrapped to (-pi, pi].
Eigen::Vector3d compose_planar(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
Eigen::Vector3d relative_planar(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
double wrap_angle(double angle);

}  // namespace omnisfm::sfm
