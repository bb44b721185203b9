#pragma once
// Plots like the paper's Figures 4 and 5 (PNG via gnuplot): each motion component that changes
// against the image index, estimates against the truth, and the x-y path from above.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/eval/trajectory_errors.h"

namespace omnisfm::app {

struct PlottedTrajectory {
  std::string name;
  std::vector<Eigen::Isometry3d> world_from_cam;
  eval::Similarity alignment;  // onto the truth
};

// Writes motion.png and path.png (and their data and gnuplot scripts) into `dir`. Returns false
// when gnuplot is missing or failed; the data files are written either way.
bool write_trajectory_plots(const std::string& dir, const std::vector<Eigen::Isometry3d>& truth,
                            const std::vector<PlottedTrajectory>& estimates);

}  // namespace omnisfm::app
