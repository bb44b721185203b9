#pragma once
// Calibration views from the input files: surveyed targets with their observations, or
// checkerboard corners with the board.

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/calib/calibration_problem.h"
#include "omnisfm/io/checkerboard_files.h"
#include "omnisfm/io/target_files.h"

namespace omnisfm::calib {

// One view per image id, in increasing order, named "image N". Throws io::InputError at the
// observation's line in `observations_file` for a target that has no survey entry.
std::vector<CalibrationView> target_views(const std::map<int, Eigen::Vector3d>& targets,
                                          const std::vector<io::TargetObservationRow>& rows,
                                          const std::string& observations_file);

// One view per image with at least one detected corner (images without are skipped), named by
// the file name, keeping its detected corners. Throws io::InputError at the image's first line
// in `corners_file` when its number of corners differs from the board's (`board_source` names
// where the board came from).
std::vector<CalibrationView> board_views(const std::vector<io::ImageCorners>& images,
                                         const std::vector<Eigen::Vector3d>& board,
                                         const std::string& corners_file,
                                         const std::string& board_source);

}  // namespace omnisfm::calib
