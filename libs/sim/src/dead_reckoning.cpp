#include "omnisfm/sim/dead_reckoning.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sim {
namespace {

// Keeps the sensors' noise independent of the tracks' for the same seed.
constexpr std::uint64_t kSensorStream = 0x5eed0d0;

double wrap_angle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// A planar pose (x, y, yaw) and its composition a (+) b.
Eigen::Vector3d compose(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  return {a.x() + c * b.x() - s * b.y(), a.y() + s * b.x() + c * b.y(), wrap_angle(a.z() + b.z())};
}

// b relative to a: the b' with a (+) b' = b.
Eigen::Vector3d relative(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double c = std::cos(a.z()), s = std::sin(a.z());
  const Eigen::Vector2d d = b.head<2>() - a.head<2>();
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(), wrap_angle(b.z() - a.z())};
}

Eigen::Vector3d planar_pose(const Eigen::Isometry3d& world_from_body) {
  const Eigen::Matrix3d& R = world_from_body.linear();
  return {world_from_body.translation().x(), world_from_body.translation().y(),
          std::atan2(R(1, 0), R(0, 0))};
}

// The rotation vector of R.
Eigen::Vector3d log_rotation(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// The frame interval [t_k, t_k+1] that holds t (the first or last one beyond the ends).
size_t interval_of(const std::vector<double>& times, double t) {
  const auto after = std::upper_bound(times.begin(), times.end(), t);
  const size_t k = after == times.begin() ? 0 : static_cast<size_t>(after - times.begin()) - 1;
  return std::min(k, times.size() - 2);
}

bool is_planar(const Dataset& d, const Eigen::Isometry3d& cam_from_body) {
  const double height = d.world_from_cam.front().translation().z();
  for (const auto& world_from_cam : d.world_from_cam) {
    const Eigen::Isometry3d world_from_body = world_from_cam * cam_from_body;
    if (world_from_body.linear()(2, 2) < 1 - 1e-12) return false;
    if (std::abs(world_from_body.translation().z() - height) > 1e-9) return false;
  }
  return true;
}

void check(const Dataset& d, const DeadReckoningOptions& o) {
  if (d.world_from_cam.size() < 2 || d.timestamps.size() != d.world_from_cam.size())
    throw std::invalid_argument("dead reckoning needs at least two frames with timestamps");
  for (size_t k = 1; k < d.timestamps.size(); ++k)
    if (!(d.timestamps[k] > d.timestamps[k - 1]))
      throw std::invalid_argument("dead reckoning needs increasing timestamps");
  if (!(o.odometry_rate_hz > 0) || !(o.gyro_rate_hz > 0))
    throw std::invalid_argument("sensor rates must be positive");
  const double noises[] = {o.odometry_position_noise, o.odometry_heading_noise,
                           o.gyro_noise_density, o.gyro_bias_sigma, o.gyro_bias_walk};
  for (double n : noises)
    if (!(n >= 0) || !std::isfinite(n))
      throw std::invalid_argument("sensor noise levels must be finite and not negative");
}

std::vector<double> sample_times(const Dataset& d, double rate_hz) {
  const double t0 = d.timestamps.front(), t1 = d.timestamps.back();
  std::vector<double> times;
  for (long i = 0;; ++i) {
    const double t = t0 + static_cast<double>(i) / rate_hz;
    if (t > t1 + 1e-9) break;
    times.push_back(t);
  }
  return times;
}

std::vector<OdometryReading> simulate_odometry(const Dataset& d,
                                               const Eigen::Isometry3d& cam_from_body,
                                               const DeadReckoningOptions& o,
                                               std::mt19937_64& rng) {
  std::vector<OdometryReading> readings;
  Eigen::Vector3d previous_true = Eigen::Vector3d::Zero();
  Eigen::Vector3d measured = Eigen::Vector3d::Zero();
  double previous_time = 0;
  for (double t : sample_times(d, o.odometry_rate_hz)) {
    const Eigen::Vector3d now_true = planar_pose(interpolate_pose(d, t) * cam_from_body);
    OdometryReading reading;
    reading.timestamp = t;
    if (!readings.empty()) {
      const Eigen::Vector3d step = relative(previous_true, now_true);
      const double distance = step.head<2>().norm();
      const double sd_position = o.odometry_position_noise * std::sqrt(distance);
      const double sd_heading = o.odometry_heading_noise * std::sqrt(distance);
      const Eigen::Vector3d read_step(
          (1 + o.odometry_scale_error) * step.x() + sd_position * standard_normal(rng),
          (1 + o.odometry_scale_error) * step.y() + sd_position * standard_normal(rng),
          (1 + o.odometry_yaw_scale_error) * step.z() + sd_heading * standard_normal(rng));
      measured = compose(measured, read_step);
      reading.velocity = read_step / (t - previous_time);
    }
    reading.pose = measured;
    readings.push_back(reading);
    previous_true = now_true;
    previous_time = t;
  }
  return readings;
}

std::vector<GyroReading> simulate_gyro(const Dataset& d, const Eigen::Isometry3d& cam_from_body,
                                       const DeadReckoningOptions& o, std::mt19937_64& rng,
                                       Eigen::Vector3d* bias_at_start) {
  // True body rates over each frame interval.
  const Eigen::Matrix3d R_cb = cam_from_body.linear();
  std::vector<Eigen::Vector3d> rates(d.world_from_cam.size() - 1);
  for (size_t k = 0; k + 1 < d.world_from_cam.size(); ++k) {
    const Eigen::Matrix3d step =
        d.world_from_cam[k].linear().transpose() * d.world_from_cam[k + 1].linear();
    rates[k] = R_cb.transpose() * log_rotation(step) / (d.timestamps[k + 1] - d.timestamps[k]);
  }
  Eigen::Vector3d bias;
  for (int axis = 0; axis < 3; ++axis) bias[axis] = o.gyro_bias_sigma * standard_normal(rng);
  *bias_at_start = bias;
  const double sd_noise = o.gyro_noise_density * std::sqrt(o.gyro_rate_hz);
  const double sd_walk = o.gyro_bias_walk / std::sqrt(o.gyro_rate_hz);
  std::vector<GyroReading> readings;
  for (double t : sample_times(d, o.gyro_rate_hz)) {
    if (!readings.empty())
      for (int axis = 0; axis < 3; ++axis) bias[axis] += sd_walk * standard_normal(rng);
    GyroReading reading;
    reading.timestamp = t;
    reading.rate = rates[interval_of(d.timestamps, t)] + bias;
    for (int axis = 0; axis < 3; ++axis) reading.rate[axis] += sd_noise * standard_normal(rng);
    readings.push_back(reading);
  }
  return readings;
}

}  // namespace

Eigen::Isometry3d interpolate_pose(const Dataset& d, double t) {
  const std::vector<double>& times = d.timestamps;
  if (t <= times.front()) return d.world_from_cam.front();
  if (t >= times.back()) return d.world_from_cam.back();
  const size_t k = interval_of(times, t);
  const double a = (t - times[k]) / (times[k + 1] - times[k]);
  const Eigen::Isometry3d& A = d.world_from_cam[k];
  const Eigen::Isometry3d& B = d.world_from_cam[k + 1];
  const Eigen::AngleAxisd step(A.linear().transpose() * B.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = A.linear() * Eigen::AngleAxisd(a * step.angle(), step.axis()).toRotationMatrix();
  pose.translation() = (1 - a) * A.translation() + a * B.translation();
  return pose;
}

Eigen::Isometry3d body_from_cam(const Dataset& d) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const bool camera_looks_down = d.world_from_cam.front().linear()(2, 2) < 0;
  if (camera_looks_down) pose.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return pose;
}

DeadReckoning simulate_dead_reckoning(const Dataset& dataset, const DeadReckoningOptions& options) {
  check(dataset, options);
  std::mt19937_64 rng(options.seed ^ kSensorStream);
  DeadReckoning result;
  result.body_from_cam = body_from_cam(dataset);
  const Eigen::Isometry3d cam_from_body = result.body_from_cam.inverse();
  if (is_planar(dataset, cam_from_body))
    result.odometry = simulate_odometry(dataset, cam_from_body, options, rng);
  result.gyro = simulate_gyro(dataset, cam_from_body, options, rng, &result.gyro_bias_at_start);
  return result;
}

}  // namespace omnisfm::sim
