#pragma once
// What a vehicle's own sensors say about its motion, in the estimators' terms (no MRPT types):
// wheel odometry, a gyro and GPS fixes, each with its noise. The MRPT plugin fills this from a
// rawlog (CObservationOdometry, CObservationIMU, CObservationGPS); the simulator from its
// dead-reckoning model.
//
// The body frame is MRPT's robot frame: x forward, y left, z up; body_from_cam places the camera
// on the vehicle. Times are seconds on the same clock as the image frames.

#include <Eigen/Geometry>
#include <vector>

namespace omnisfm::sfm {

// Planar wheel odometry: the body's pose (x, y, yaw) relative to where the odometry started.
struct OdometrySample {
  double timestamp = 0;
  Eigen::Vector3d pose{0, 0, 0};
};

// Angular rates about the body's x, y, z axes.
struct GyroSample {
  double timestamp = 0;
  Eigen::Vector3d rate{0, 0, 0};
};

// A GPS antenna position in a local east-north-up frame (metres, about a geodetic origin).
struct GpsSample {
  double timestamp = 0;
  Eigen::Vector3d enu{0, 0, 0};
  double horizontal_sigma = 1.0;  // metres, per axis
  double vertical_sigma = 2.0;
};

struct OdometryNoise {
  double position_sigma = 0.01;  // metres per sqrt(metre travelled), per axis
  double heading_sigma = 0.01;   // radians per sqrt(metre travelled)
  // How well the wheels' scale (MotionSensors::odometry_scale) is known, relative; the batch
  // estimates the scale within it. 0 holds it fixed.
  double scale_sigma = 0.02;
};

struct GyroNoise {
  double noise_density = 2e-4;  // rad/s per sqrt(Hz)
  double bias_sigma = 5e-3;     // rad/s, prior on the bias at the start
  double bias_walk = 2e-5;      // rad/s^2 per sqrt(Hz)
};

struct MotionSensors {
  Eigen::Isometry3d body_from_cam = Eigen::Isometry3d::Identity();
  Eigen::Vector3d antenna_in_body{0, 0, 0};
  std::vector<OdometrySample> odometry;  // in time order; empty when there is none
  OdometryNoise odometry_noise;
  // True distance per distance the odometry reads (a worn tyre reads long): a calibration, e.g.
  // the odometry_scale an earlier run with GPS estimated.
  double odometry_scale = 1.0;
  std::vector<GyroSample> gyro;  // in time order; empty when there is none
  GyroNoise gyro_noise;
  std::vector<GpsSample> gps;  // in time order; empty when there is none
  bool empty() const { return odometry.empty() && gyro.empty() && gps.empty(); }
};

}  // namespace omnisfm::sfm
