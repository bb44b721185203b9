#pragma once
// Positions in geodetic coordinates as a vnlog table:
//   # timestamp latitude longitude height
// (degrees, metres above the WGS84 ellipsoid), from positions in a local ENU frame.
//
// MRPT-free: the omnisfm command calls this without MRPT headers.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "omnisfm/mrpt_plugin/local_enu_frame.h"

namespace omnisfm::mrpt_plugin {

// Writes the table to `path` atomically, with `what` as a comment; throws std::runtime_error when
// it cannot, std::invalid_argument when the two lists differ in length.
void write_geodetic_table(const std::string& path, const std::vector<double>& timestamps,
                          const std::vector<Eigen::Vector3d>& enu_positions,
                          const LocalEnuFrame& enu, const std::string& what);

}  // namespace omnisfm::mrpt_plugin
