#pragma once
// The estimators' cam_from_world poses as trajectories are compared: world_from_cam.

#include <Eigen/Geometry>
#include <vector>

namespace omnisfm::sfm {

inline std::vector<Eigen::Isometry3d> inverted(const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Isometry3d> out;
  for (const auto& T : poses) out.push_back(T.inverse());
  return out;
}

}  // namespace omnisfm::sfm
