#pragma once
// `omnisfm run` with GPS: the trajectory in geodetic coordinates, geodetic.vnl
// (# timestamp latitude longitude height: every frame's camera centre, degrees and metres above
// the WGS84 ellipsoid).
//
// The estimate's world frame is placed in the local ENU frame of the fixes by the similarity that
// best maps the estimated antenna positions at the fixes' times onto the fixes (Horn's closed
// form): vision alone leaves that frame's pose and scale free. An estimate already in ENU (GPS
// fused into it) is taken as it is: the transform is the identity, the RMS that of the fixes
// against it.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/eval/similarity_alignment.h"
#include "omnisfm/mrpt_plugin/local_enu_frame.h"
#include "omnisfm/sfm/motion_sensors.h"

namespace omnisfm::app {

struct GpsFit {
  eval::Similarity enu_from_world;
  int fixes = 0;         // fixes within the trajectory's time span, used for the fit
  double rms_m = 0;      // of the fixes' residuals after the fit
};

// Throws std::invalid_argument when fewer than 3 fixes fall within the frames' times or they are
// collinear.
GpsFit fit_trajectory_to_gps(const std::vector<Eigen::Isometry3d>& world_from_cam,
                             const std::vector<double>& frame_times,
                             const sfm::MotionSensors& sensors, bool world_is_enu);

// Writes geodetic.vnl into `path`; throws std::runtime_error when it cannot.
void write_geodetic_trajectory(const std::string& path,
                               const std::vector<Eigen::Isometry3d>& world_from_cam,
                               const std::vector<double>& frame_times, const GpsFit& fit,
                               const mrpt_plugin::LocalEnuFrame& enu);

}  // namespace omnisfm::app
