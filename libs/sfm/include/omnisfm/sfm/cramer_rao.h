#pragma once
// The Cramer-Rao bound of the batch problem: the covariance no unbiased estimator can beat, the
// inverse of the Fisher information J^T J / sigma^2 at the true poses and points, in the batch's
// gauge (the first pose fixed).

#include <Eigen/Geometry>
#include <map>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/core/track_observation.h"

namespace omnisfm::sfm {

struct PositionBound {
  // RMS over frames 1.. of the bound on the camera centres' error, in the batch's gauge (the
  // first pose fixed), and after the best similarity alignment onto the truth removes the 7
  // gauge freedoms a monocular comparison ignores (to first order).
  double rms_fixed_first_pose_m = 0;
  double rms_after_similarity_m = 0;
};

// observations: which track each frame sees (the pixels are not used); world_from_cam and points:
// the truth. Throws std::invalid_argument when the information matrix is singular.
PositionBound camera_position_bound(
    const camera::CatadioptricCamera& camera, const std::vector<core::TrackObservation>& observations,
    const std::vector<Eigen::Isometry3d>& world_from_cam,
    const std::map<int, Eigen::Vector3d>& points, double pixel_sigma);

}  // namespace omnisfm::sfm
