#pragma once
// `omnisfm simulate --rawlog`: dataset.rawlog in the simulated dataset's folder, written by the
// MRPT plugin. omnisfm links the plugin only when built with it (OMNISFM_BUILD_MRPT_PLUGIN);
// this is the one place that knows.

#include <cstdint>
#include <string>

#include "omnisfm/sim/dataset.h"
#include "omnisfm/sim/dataset_writer.h"

namespace omnisfm::app {

// Whether this omnisfm can write rawlogs.
bool can_write_rawlogs();

// Writes <dir>/dataset.rawlog: the tracks, the rendered images/NNNNNN.png when `with_images`,
// odometry and gyro readings drawn with `seed`, and with `with_gps` GPS fixes (then also
// ground_truth_enu.tum and ground_truth_geodetic.vnl); sets *summary to a phrase saying what it
// holds.
// Throws std::logic_error when !can_write_rawlogs().
sim::FolderWriter simulated_rawlog_writer(const sim::Dataset& dataset, std::uint64_t seed,
                                          bool with_images, bool with_gps, std::string* summary);

}  // namespace omnisfm::app
