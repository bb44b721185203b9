#pragma once
// The ground truth of a simulated outdoor dataset in the GPS's terms, written beside its rawlog:
//   ground_truth_enu.tum        world_from_cam of every frame with the world the local ENU frame
//                               about the GPS origin (sim::GpsTrack::enu_from_world applied)
//   ground_truth_geodetic.vnl   # timestamp latitude longitude height: every frame's camera centre
//                               (degrees, metres above the WGS84 ellipsoid)
// Timestamps are on the rawlog's clock (start_time plus the dataset's time), as a replay of the
// rawlog writes its trajectories.
//
// MRPT-free: the omnisfm command calls this without MRPT headers.

#include <string>

#include "omnisfm/sim/dataset.h"
#include "omnisfm/sim/gps_receiver.h"

namespace omnisfm::mrpt_plugin {

// Writes both files into the existing folder `dir`; throws std::runtime_error when it cannot.
void write_gps_ground_truth(const sim::Dataset& dataset, const sim::GpsTrack& gps,
                            double start_time, const std::string& dir);

}  // namespace omnisfm::mrpt_plugin
