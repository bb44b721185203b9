#pragma once
// Two trajectories' poses paired by timestamp, as `omnisfm eval` compares an estimate with the
// truth: each estimated pose with the true one of the same time.

#include <Eigen/Geometry>
#include <vector>

#include "omnisfm/io/tum_trajectory.h"

namespace omnisfm::eval {

struct PairedPoses {
  std::vector<Eigen::Isometry3d> estimate, truth;  // world_from_cam, pair by pair
};

// Both trajectories sorted by time (as TUM files are); times within `tolerance_s` are the same.
PairedPoses pair_by_timestamp(const std::vector<io::StampedPose>& estimate,
                              const std::vector<io::StampedPose>& truth,
                              double tolerance_s = 1e-6);

}  // namespace omnisfm::eval
