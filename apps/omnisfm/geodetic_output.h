#pragma once
// `omnisfm run` with GPS: the trajectory in geodetic coordinates, geodetic.vnl
// (# timestamp latitude longitude height: every frame's camera centre, degrees and metres above
// the WGS84 ellipsoid).
// The estimate is in the fixes' local ENU frame (the fused pipeline places it there).

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/mrpt_plugin/local_enu_frame.h"

namespace omnisfm::app {

// Writes geodetic.vnl into `path`; throws std::runtime_error when it cannot.
void write_geodetic_trajectory(const std::string& path,
                               const std::vector<Eigen::Isometry3d>& world_from_cam,
                               const std::vector<double>& frame_times,
                               const mrpt_plugin::LocalEnuFrame& enu);

}  // namespace omnisfm::app
