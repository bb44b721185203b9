#include "omnisfm/sfm/frame_motion.h"

#include <algorithm>
#include <cmath>

#include "so3.h"

namespace omnisfm::sfm {
namespace {

// Below this distance an increment's covariance stops shrinking: a wheel that has not turned
// still says so only to within its resolution.
constexpr double kMinOdometryDistance = 1e-3;

// Sensor and frame clocks agree to within this.
constexpr double kTimeTolerance = 1e-6;

template <typename Sample>
bool covers(const std::vector<Sample>& samples, double t0, double t1) {
  return !samples.empty() && t0 >= samples.front().timestamp - kTimeTolerance &&
         t1 <= samples.back().timestamp + kTimeTolerance;
}

}  // namespace

double wrap_angle(double angle) { return std::atan2(std::sin(angle), std::cos(angle)); }

Eigen::Vector3d compose_planar(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  return {a.x() + c * b.x() - s * b.y(), a.y() + s * b.x() + c * b.y(), wrap_angle(a.z() + b.z())};
}

Eigen::Vector3d relative_planar(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  const Eigen::Vector2d d = b.head<2>() - a.head<2>();
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), wrap_angle(b.z() - a.z())};
}

bool interpolate_odometry(const std::vector<OdometrySample>& odometry, double t,
                          Eigen::Vector3d* pose) {
  if (!covers(odometry, t, t)) return false;
  const auto after = std::upper_bound(
      odometry.begin(), odometry.end(), t,
      [](double time, const OdometrySample& s) { return time < s.timestamp; });
  if (after == odometry.begin()) {
    *pose = odometry.front().pose;
    return true;
  }
  if (after == odometry.end()) {
    *pose = odometry.back().pose;
    return true;
  }
  const OdometrySample& a = *(after - 1);
  const OdometrySample& b = *after;
  const double span = b.timestamp - a.timestamp;
  const double alpha = span > 0 ? (t - a.timestamp) / span : 0;
  // Interpolated as the increment a -> b scaled, so that yaw wraps correctly.
  *pose = compose_planar(a.pose, alpha * relative_planar(a.pose, b.pose));
  return true;
}

OdometryIncrement odometry_increment(const std::vector<OdometrySample>& odometry,
                                     const OdometryNoise& noise, double t0, double t1) {
  OdometryIncrement increment;
  Eigen::Vector3d from, to;
  if (!interpolate_odometry(odometry, t0, &from) || !interpolate_odometry(odometry, t1, &to))
    return increment;
  increment.valid = true;
  increment.delta = relative_planar(from, to);
  increment.distance = increment.delta.head<2>().norm();
  const double d = std::max(increment.distance, kMinOdometryDistance);
  increment.covariance = Eigen::Vector3d(noise.position_sigma * noise.position_sigma * d,
                                         noise.position_sigma * noise.position_sigma * d,
                                         noise.heading_sigma * noise.heading_sigma * d)
                             .asDiagonal();
  return increment;
}

GyroIncrement integrate_gyro(const std::vector<GyroSample>& gyro, const GyroNoise& noise,
                             double t0, double t1, const Eigen::Vector3d& bias_lin) {
  GyroIncrement increment;
  if (!covers(gyro, t0, t1) || !(t1 > t0)) return increment;
  increment.valid = true;
  increment.dt = t1 - t0;
  increment.bias_lin = bias_lin;
  const double rate_variance = noise.noise_density * noise.noise_density;
  // The sample whose hold interval contains t0.
  auto it = std::upper_bound(gyro.begin(), gyro.end(), t0,
                             [](double time, const GyroSample& s) { return time < s.timestamp; });
  size_t i = it == gyro.begin() ? 0 : static_cast<size_t>(it - gyro.begin()) - 1;
  double t = t0;
  while (t < t1) {
    const double end = i + 1 < gyro.size() ? std::clamp(gyro[i + 1].timestamp, t, t1) : t1;
    const double dt = end - t;
    if (dt > 0) {
      // dR_{j+1} = dR_j E, with E = Exp((w - b) dt); a bias change db enters E as
      // Exp(-J_right (w - b) dt) db dt), hence the recursion for J and the covariance.
      const Eigen::Vector3d angle = (gyro[i].rate - bias_lin) * dt;
      const Eigen::Matrix3d E = so3::exp(angle);
      const Eigen::Matrix3d J_right = so3::right_jacobian(angle);
      increment.J_rotation_bias = E.transpose() * increment.J_rotation_bias - J_right * dt;
      increment.covariance = E.transpose() * increment.covariance * E +
                             J_right * J_right.transpose() * (rate_variance * dt);
      increment.rotation = increment.rotation * E;
    }
    t = end;
    ++i;
  }
  return increment;
}

FrameMotion frame_motion(const MotionSensors& sensors, double t0, double t1,
                         const Eigen::Vector3d& gyro_bias_lin) {
  FrameMotion m;
  m.odometry = odometry_increment(sensors.odometry, sensors.odometry_noise, t0, t1);
  m.gyro = integrate_gyro(sensors.gyro, sensors.gyro_noise, t0, t1, gyro_bias_lin);
  return m;
}

std::vector<FrameMotion> frame_motions(const MotionSensors& sensors,
                                       const std::vector<double>& frame_timestamps,
                                       const Eigen::Vector3d& gyro_bias_lin) {
  std::vector<FrameMotion> motions;
  for (size_t k = 0; k + 1 < frame_timestamps.size(); ++k)
    motions.push_back(
        frame_motion(sensors, frame_timestamps[k], frame_timestamps[k + 1], gyro_bias_lin));
  return motions;
}

}  // namespace omnisfm::sfm
