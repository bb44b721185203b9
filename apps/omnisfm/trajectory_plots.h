#pragma once
// Plots like the paper's Figures 4 and 5 (PNG via gnuplot): each motion component that changes
// against the image index, estimates against the truth, and the x-y path from above.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/eval/truth_comparison.h"

namespace omnisfm::app {

// Writes motion.png and path.png (and their data and gnuplot scripts) into `dir`. Returns false
// when gnuplot is missing or failed; the data files are written either way.
bool write_trajectory_plots(const std::string& dir, const std::vector<Eigen::Isometry3d>& truth,
                            const std::vector<eval::ComparedTrajectory>& estimates);

}  // namespace omnisfm::app
