#pragma once
// Which way a pose points. Trajectories cross module boundaries as world_from_cam, the camera's
// pose in the world: TUM files, MRPT's CPose3D of a camera, the simulator's truth and the
// comparisons with it all use it. The estimators hold cam_from_world where their math lives (the
// batch's parameter blocks, the filter's state and its covariance's coordinates), as projecting a
// world point needs it; they turn it into world_from_cam once, here, where their results leave.

#include <Eigen/Geometry>
#include <vector>

namespace omnisfm::core {

// Each pose the other way round: world_from_cam of cam_from_world poses, and back.
inline std::vector<Eigen::Isometry3d> inverted(const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(poses.size());
  for (const Eigen::Isometry3d& T : poses) out.push_back(T.inverse());
  return out;
}

}  // namespace omnisfm::core
