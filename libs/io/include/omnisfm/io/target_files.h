#pragma once
// Surveyed targets and their observations (DESIGN.md section 3):
//   targets.vnl       `# target x y z`    world position of each target id, metres
//   observations.vnl  `# image target u v` the pixel of a target in an image
// Each row keeps its line so that a later check (a target without a survey entry) can point at it.

#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace omnisfm::io {

struct TargetObservationRow {
  int image = 0;
  int target = 0;
  Eigen::Vector2d pixel{0, 0};
  int line = 0;
};

// Target id -> position. Throws InputError naming the file and line for a missing column, a
// non-integer or negative id, a duplicate id, or a coordinate that is missing or not finite.
std::map<int, Eigen::Vector3d> read_targets(const std::string& path);

// In file order. Throws InputError naming the file and line for a missing column, a non-integer
// image or target, a missing or non-finite pixel, or a target seen twice in one image.
std::vector<TargetObservationRow> read_target_observations(const std::string& path);

}  // namespace omnisfm::io
