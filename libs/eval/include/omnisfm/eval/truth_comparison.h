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
  std::string report;  // a figures_line per estimate (and per rigid alignment)
  std::vector<ComparedTrajectory> estimates;
  std::vector<Eigen::Isometry3d> truth;  // world_from_cam, frame by frame
};

// The result's estimates against `truth`, paired frame by frame. Throws io::InputError naming
// `truth_file` when it has another number of poses than the result has frames.
TruthComparison compare_with_truth(const sfm::SfmResult& result, bool batch_ran,
                                   const std::vector<io::StampedPose>& truth,
                                   const std::string& truth_file, bool rigid_too = false);

}  // namespace omnisfm::eval
