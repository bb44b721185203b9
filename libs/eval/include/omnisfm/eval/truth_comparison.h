#pragma once
// A shape-from-motion result against a ground-truth trajectory, as the sfm and run verbs report it:
// the paper's figures of each estimate (the filter's, and the batch's when it ran) after a
// similarity alignment and, for estimates whose scale is known, a rigid one.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::eval {

// One line of the paper's figures: "NAME translation ... m mean (...% of ... m), rotation ...".
std::string figures_line(const std::string& name, const TrajectoryErrors& errors);

struct ComparedTrajectory {
  std::string name;  // "online", "batch"
  std::vector<Eigen::Isometry3d> world_from_cam;
  Similarity alignment;  // onto the truth
};

struct TruthComparison {
  // A figures_line per estimate (and per rigid alignment), after a line on a truth left unpaired.
  std::string report;
  std::vector<ComparedTrajectory> estimates;
  std::vector<Eigen::Isometry3d> truth;  // world_from_cam, frame by frame
};

// The result's estimates against `truth`, paired frame by frame. A truth longer than the result
// (the last images, dark or lost, gave no tracks, so the tracks end early) is compared over its
// first frames, and the report says so in its first line. Throws io::InputError naming
// `truth_file` when it has fewer poses than the result has frames.
TruthComparison compare_with_truth(const sfm::SfmResult& result, bool batch_ran,
                                   const std::vector<io::StampedPose>& truth,
                                   const std::string& truth_file, bool rigid_too = false);

}  // namespace omnisfm::eval
