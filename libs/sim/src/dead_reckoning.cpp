#include "omnisfm/sim/dead_reckoning.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sim {
namespace {

// Keep the sensors' noise independent of the tracks' and of each other for the same seed.
constexpr std::uint64_t kSensorStream = 0x5eed0d0;
constexpr std::uint64_t kGyroStream = 0x5eed6e0;

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

void check(const DeadReckoningOptions& o) {
  if (!(o.odometry_rate_hz > 0) || !(o.gyro_rate_hz > 0))
    throw std::invalid_argument("sensor rates must be positive");
  const double noises[] = {o.odometry_position_noise, o.odometry_heading_noise,
                           o.gyro_noise_density, o.gyro_bias_sigma, o.gyro_bias_walk};
  for (double n : noises)
    if (!(n >= 0) || !std::isfinite(n))
      throw std::invalid_argument("sensor noise levels must be finite and not negative");
}

void check(const Dataset& d, const DeadReckoningOptions& o) {
  if (d.world_from_cam.size() < 2 || d.timestamps.size() != d.world_from_cam.size())
    throw std::invalid_argument("dead reckoning needs at least two frames with timestamps");
  for (size_t k = 1; k < d.timestamps.size(); ++k)
    if (!(d.timestamps[k] > d.timestamps[k - 1]))
      throw std::invalid_argument("dead reckoning needs increasing timestamps");
  check(o);
}

// The sample times t0 + i / rate up to t1 (and 1e-9 beyond, for rounding): how many there are.
long sample_count(double t0, double t1, double rate_hz) {
  long i = 0;
  while (t0 + static_cast<double>(i) / rate_hz <= t1 + 1e-9) ++i;
  return i;
}

// The pose a of the way from A to B: linear position, geodesic rotation.
Eigen::Isometry3d between(const Eigen::Isometry3d& A, const Eigen::Isometry3d& B, double a) {
  const Eigen::AngleAxisd step(A.linear().transpose() * B.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = A.linear() * Eigen::AngleAxisd(a * step.angle(), step.axis()).toRotationMatrix();
  pose.translation() = (1 - a) * A.translation() + a * B.translation();
  return pose;
}

}  // namespace

DeadReckoningStream::DeadReckoningStream(const Eigen::Isometry3d& body_from_cam,
                                         const DeadReckoningOptions& options, bool with_odometry)
    : cam_from_body_(body_from_cam.inverse()),
      options_(options),
      with_odometry_(with_odometry),
      odometry_rng_(options.seed ^ kSensorStream),
      gyro_rng_(options.seed ^ kGyroStream) {
  check(options);
}

void DeadReckoningStream::add_frame(double timestamp, const Eigen::Isometry3d& world_from_cam,
                                    std::vector<OdometryReading>* odometry,
                                    std::vector<GyroReading>* gyro) {
  if (frames_++ == 0) {
    start_time_ = t0_ = t1_ = timestamp;
    A_ = B_ = world_from_cam;
    for (int axis = 0; axis < 3; ++axis)
      bias_[axis] = options_.gyro_bias_sigma * standard_normal(gyro_rng_);
    bias_at_start_ = bias_;
    return;
  }
  if (!(timestamp > t1_)) throw std::invalid_argument("dead reckoning needs increasing timestamps");
  A_ = B_;
  t0_ = t1_;
  B_ = world_from_cam;
  t1_ = timestamp;
  body_rate_ = cam_from_body_.linear().transpose() *
               log_rotation(A_.linear().transpose() * B_.linear()) / (t1_ - t0_);
  sample(t1_, false, odometry, gyro);
}

void DeadReckoningStream::finish(std::vector<OdometryReading>* odometry,
                                 std::vector<GyroReading>* gyro) {
  if (frames_ > 0) sample(t1_ + 1e-9, true, odometry, gyro);
}

void DeadReckoningStream::sample(double to, bool closed, std::vector<OdometryReading>* odometry,
                                 std::vector<GyroReading>* gyro) {
  const auto before = [&](double t) { return closed ? t <= to : t < to; };
  if (with_odometry_)
    for (double t; before(t = start_time_ + static_cast<double>(next_odometry_) /
                                               options_.odometry_rate_hz);
         ++next_odometry_)
      odometry_reading(t, odometry);
  for (double t;
       before(t = start_time_ + static_cast<double>(next_gyro_) / options_.gyro_rate_hz);
       ++next_gyro_)
    gyro_reading(t, gyro);
}

void DeadReckoningStream::odometry_reading(double t, std::vector<OdometryReading>* out) {
  const Eigen::Isometry3d world_from_cam =
      t <= t0_ ? A_ : t >= t1_ ? B_ : between(A_, B_, (t - t0_) / (t1_ - t0_));
  const Eigen::Vector3d now_true = planar_pose(world_from_cam * cam_from_body_);
  const DeadReckoningOptions& o = options_;
  std::mt19937_64& rng = odometry_rng_;
  OdometryReading reading;
  reading.timestamp = t;
  if (next_odometry_ > 0) {
    const Eigen::Vector3d step = relative(previous_true_, now_true);
    const double distance = step.head<2>().norm();
    const double sd_position = o.odometry_position_noise * std::sqrt(distance);
    const double sd_heading = o.odometry_heading_noise * std::sqrt(distance);
    const Eigen::Vector3d noise = standard_normal_3d(rng);
    const Eigen::Vector3d read_step(
        (1 + o.odometry_scale_error) * step.x() + sd_position * noise.x(),
        (1 + o.odometry_scale_error) * step.y() + sd_position * noise.y(),
        (1 + o.odometry_yaw_scale_error) * step.z() + sd_heading * noise.z());
    measured_ = compose(measured_, read_step);
    reading.velocity = read_step / (t - previous_odometry_time_);
  }
  reading.pose = measured_;
  out->push_back(reading);
  previous_true_ = now_true;
  previous_odometry_time_ = t;
}

void DeadReckoningStream::gyro_reading(double t, std::vector<GyroReading>* out) {
  const double sd_noise = options_.gyro_noise_density * std::sqrt(options_.gyro_rate_hz);
  const double sd_walk = options_.gyro_bias_walk / std::sqrt(options_.gyro_rate_hz);
  if (next_gyro_ > 0)
    for (int axis = 0; axis < 3; ++axis) bias_[axis] += sd_walk * standard_normal(gyro_rng_);
  GyroReading reading;
  reading.timestamp = t;
  reading.rate = body_rate_ + bias_;
  for (int axis = 0; axis < 3; ++axis) reading.rate[axis] += sd_noise * standard_normal(gyro_rng_);
  out->push_back(reading);
}

Eigen::Isometry3d interpolate_pose(const Dataset& d, double t) {
  const std::vector<double>& times = d.timestamps;
  if (t <= times.front()) return d.world_from_cam.front();
  if (t >= times.back()) return d.world_from_cam.back();
  const size_t k = interval_of(times, t);
  return between(d.world_from_cam[k], d.world_from_cam[k + 1],
                 (t - times[k]) / (times[k + 1] - times[k]));
}

Eigen::Isometry3d extrapolate_pose(const Dataset& d, double t) {
  const std::vector<double>& times = d.timestamps;
  if (times.size() < 2) return d.world_from_cam.front();
  const size_t k = interval_of(times, t);
  return between(d.world_from_cam[k], d.world_from_cam[k + 1],
                 (t - times[k]) / (times[k + 1] - times[k]));
}

Eigen::Isometry3d body_from_cam(const Dataset& d) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const bool camera_looks_down = d.world_from_cam.front().linear()(2, 2) < 0;
  if (camera_looks_down) pose.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  return pose;
}

DeadReckoning simulate_dead_reckoning(const Dataset& dataset, const DeadReckoningOptions& options) {
  check(dataset, options);
  DeadReckoning result;
  result.body_from_cam = body_from_cam(dataset);
  const bool planar = is_planar(dataset, result.body_from_cam.inverse());
  DeadReckoningStream stream(result.body_from_cam, options, planar);
  // One generator for both sensors, the odometry's draws (six per reading after the first)
  // before the gyro's: the readings a seed gave before there was a stream.
  stream.gyro_rng_ = stream.odometry_rng_;
  if (planar)
    stream.gyro_rng_.discard(
        6 * (sample_count(dataset.timestamps.front(), dataset.timestamps.back(),
                          options.odometry_rate_hz) -
             1));
  for (size_t k = 0; k < dataset.world_from_cam.size(); ++k)
    stream.add_frame(dataset.timestamps[k], dataset.world_from_cam[k], &result.odometry,
                     &result.gyro);
  stream.finish(&result.odometry, &result.gyro);
  result.gyro_bias_at_start = stream.gyro_bias_at_start();
  result.gyro_bias_at_end = stream.gyro_bias();
  return result;
}

}  // namespace omnisfm::sim
