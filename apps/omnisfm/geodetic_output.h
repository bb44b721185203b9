#pragma once
// `omnisfm run` with GPS: the trajectory in geodetic coordinates, geodetic.vnl
// (# timestamp latitude longitude height: every frame's camera centre, degrees and metres above
// the WGS84 ellipsoid).
//
// The estimate is in the fixes' local ENU frame (the fused pipeline places it there); the fixes'
// residuals against it (the antenna's position between the frames around each fix) are reported.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/mrpt_plugin/local_enu_frame.h"
#include "omnisfm/sfm/motion_sensors.h"

namespace omnisfm::app {

struct GpsFit {
  int fixes = 0;     // fixes within the trajectory's time span
  double rms_m = 0;  // of the fixes against the estimated antenna positions
};

// world_from_cam in ENU. Fixes outside the frames' times are left out.
GpsFit gps_fit_of(const std::vector<Eigen::Isometry3d>& world_from_cam,
                  const std::vector<double>& frame_times, const sfm::MotionSensors& sensors);

// Writes geodetic.vnl into `path`; throws std::runtime_error when it cannot.
void write_geodetic_trajectory(const std::string& path,
                               const std::vector<Eigen::Isometry3d>& world_from_cam,
                               const std::vector<double>& frame_times,
                               const mrpt_plugin::LocalEnuFrame& enu);

}  // namespace omnisfm::app
