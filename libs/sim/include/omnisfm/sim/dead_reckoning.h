#pragma once
// Dead-reckoning sensors on the simulated rig: wheel odometry that drifts and a gyro with noise
// and bias, measured from the ground-truth motion of a dataset.
//
// The vehicle ("body") frame is MRPT's robot frame: x forward, y left, z up. It is the camera
// frame C turned, when C's z axis points down (the lab's inverted rig), by pi about x; its origin
// is the camera's centre. Between frames the body moves at constant velocity and constant
// angular velocity (linear position, geodesic rotation), so the true rates are piecewise constant.
//
// Odometry (planar motion only: the body's z stays vertical and its height constant; empty
// otherwise, as for the crane): readings at a fixed rate, each the pose (x, y, yaw) of the body
// relative to where the odometry started, integrated from increments (dx, dy, dyaw) measured as
//   dx' = (1 + scale_error) dx + n,  dy' = (1 + scale_error) dy + n,   n ~ N(0, position_noise^2 d)
//   dyaw' = (1 + yaw_scale_error) dyaw + m,                            m ~ N(0, heading_noise^2 d)
// with d the true distance of the increment: errors grow with distance, not time, as a wheel's do.
//
// Gyro: angular rates about the body's axes at a fixed rate,
//   w' = w + b + n,   n ~ N(0, noise_density^2 rate),
// with the bias b drawn once per axis from N(0, bias_sigma^2) and then a random walk of
// bias_walk^2 / rate per sample.

#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <vector>

#include "omnisfm/sim/dataset.h"

namespace omnisfm::sim {

struct DeadReckoningOptions {
  std::uint64_t seed = 1;
  double odometry_rate_hz = 10;
  double odometry_scale_error = 0.015;     // distances read 1.5 % long (a worn wheel radius)
  double odometry_yaw_scale_error = 0.01;  // turns read 1 % large (the wheel base)
  double odometry_position_noise = 0.002;  // m per sqrt(m travelled)
  double odometry_heading_noise = 0.01;    // rad per sqrt(m travelled)
  double gyro_rate_hz = 100;
  double gyro_noise_density = 2e-4;  // rad/s per sqrt(Hz), a consumer MEMS gyro
  double gyro_bias_sigma = 5e-3;     // rad/s, the bias at switch-on
  double gyro_bias_walk = 2e-5;      // rad/s^2 per sqrt(Hz)
};

struct OdometryReading {
  double timestamp = 0;               // seconds, the dataset's clock
  Eigen::Vector3d pose{0, 0, 0};      // x, y, yaw relative to the first reading
  Eigen::Vector3d velocity{0, 0, 0};  // vx, vy (body frame), yaw rate: the last increment / dt
};

struct GyroReading {
  double timestamp = 0;
  Eigen::Vector3d rate{0, 0, 0};  // rad/s about the body's x, y, z
};

struct DeadReckoning {
  Eigen::Isometry3d body_from_cam = Eigen::Isometry3d::Identity();  // the camera on the vehicle
  std::vector<OdometryReading> odometry;  // empty when the motion is not planar
  std::vector<GyroReading> gyro;
  Eigen::Vector3d gyro_bias_at_start{0, 0, 0};  // the truth, for checking estimators
  Eigen::Vector3d gyro_bias_at_end{0, 0, 0};    // after its walk, at the last reading
};

// Throws std::invalid_argument for a dataset with fewer than two frames or timestamps that do not
// increase, and for rates that are not positive or noise levels that are negative.
DeadReckoning simulate_dead_reckoning(const Dataset& dataset, const DeadReckoningOptions& options);

// The same sensors made as the frames come, for drives of any length (sim::EndlessDrive): each
// frame's pose brings the readings since the previous frame's.
class DeadReckoningStream {
 public:
  // with_odometry: the motion is planar (the body's z vertical, its height constant). Throws
  // std::invalid_argument for rates that are not positive or noise levels that are negative.
  DeadReckoningStream(const Eigen::Isometry3d& body_from_cam, const DeadReckoningOptions& options,
                      bool with_odometry);

  // The next frame (times increasing; throws std::invalid_argument otherwise): appends the
  // readings timed from the previous frame's time up to, not including, this one's (from this
  // time on for the first frame, whose readings come with the second).
  void add_frame(double timestamp, const Eigen::Isometry3d& world_from_cam,
                 std::vector<OdometryReading>* odometry, std::vector<GyroReading>* gyro);
  // After the last frame: the readings at its time.
  void finish(std::vector<OdometryReading>* odometry, std::vector<GyroReading>* gyro);
  const Eigen::Vector3d& gyro_bias_at_start() const { return bias_at_start_; }
  // The bias at the last reading made.
  const Eigen::Vector3d& gyro_bias() const { return bias_; }

 private:
  friend DeadReckoning simulate_dead_reckoning(const Dataset&, const DeadReckoningOptions&);
  // The readings of both sensors timed in [from, to) (to included when `closed`) over the frame
  // interval from A (at t0) to B (at t1).
  void sample(double to, bool closed, std::vector<OdometryReading>* odometry,
              std::vector<GyroReading>* gyro);
  void odometry_reading(double t, std::vector<OdometryReading>* out);
  void gyro_reading(double t, std::vector<GyroReading>* out);

  Eigen::Isometry3d cam_from_body_;
  DeadReckoningOptions options_;
  bool with_odometry_;
  std::mt19937_64 odometry_rng_, gyro_rng_;
  Eigen::Vector3d bias_, bias_at_start_;
  // The frame interval being sampled: from frame A at t0 to frame B at t1.
  int frames_ = 0;
  double t0_ = 0, t1_ = 0;
  Eigen::Isometry3d A_ = Eigen::Isometry3d::Identity(), B_ = Eigen::Isometry3d::Identity();
  Eigen::Vector3d body_rate_{0, 0, 0};
  long next_odometry_ = 0, next_gyro_ = 0;  // sample indices from the first frame's time
  double start_time_ = 0;
  Eigen::Vector3d previous_true_{0, 0, 0}, measured_{0, 0, 0};
  double previous_odometry_time_ = 0;
};

// world_from_cam at time t, between the frames around it (clamped to the first and last frame).
Eigen::Isometry3d interpolate_pose(const Dataset& dataset, double t);
// The same, but before the first frame and after the last the motion of the first or last
// interval goes on (a camera's exposure about its first frame began before that frame's time).
Eigen::Isometry3d extrapolate_pose(const Dataset& dataset, double t);

// The camera-to-body rotation that the odometry and the gyro use for this dataset.
Eigen::Isometry3d body_from_cam(const Dataset& dataset);

}  // namespace omnisfm::sim
