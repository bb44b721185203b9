#pragma once
// A simulated GPS receiver on the rig: antenna positions in a local east-north-up (ENU) frame,
// for an outdoor variant of a dataset.
//
// The dataset's world frame (z up) is placed in ENU by enu_from_world: turned about the vertical by
// world_heading (the angle from east to the world's x axis, counter-clockwise) and moved by
// world_origin_enu. The ENU frame's origin is the geodetic point (latitude, longitude, height);
// turning ENU into geodetic coordinates is the caller's (GeographicLib's LocalCartesian), so that
// this library stays free of geodesy. Fixes come at a fixed rate, each the true antenna position
// plus independent Gaussian noise, horizontal and vertical.

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "omnisfm/sim/dataset.h"

namespace omnisfm::sim {

struct GpsOptions {
  std::uint64_t seed = 1;
  double rate_hz = 1;
  double horizontal_sigma = 0.02;  // metres per axis: an RTK fix
  double vertical_sigma = 0.04;
  Eigen::Vector3d antenna_in_body{0, 0, 0.25};  // on a mast above the camera
  double world_heading = 0.6;                     // radians from east to the world's x axis
  Eigen::Vector3d world_origin_enu{0, 0, 0};
  double latitude_deg = 40.4435;  // the ENU origin
  double longitude_deg = -79.9455;
  double height_m = 280;
};

struct GpsReading {
  double timestamp = 0;
  Eigen::Vector3d enu{0, 0, 0};  // measured antenna position
};

struct GpsTrack {
  Eigen::Isometry3d enu_from_world = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d body_from_cam = Eigen::Isometry3d::Identity();
  Eigen::Vector3d antenna_in_body{0, 0, 0};
  double latitude_deg = 0, longitude_deg = 0, height_m = 0;  // the ENU origin
  double horizontal_sigma = 0, vertical_sigma = 0;
  std::vector<GpsReading> fixes;
};

// Throws std::invalid_argument for a dataset with fewer than two frames or timestamps that do not
// increase, a rate that is not positive, or noise that is negative.
GpsTrack simulate_gps(const Dataset& dataset, const GpsOptions& options);

}  // namespace omnisfm::sim
