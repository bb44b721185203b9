#pragma once
// The reprojection residual of every observation under an estimate: what the residual plots of
// `omnisfm sfm` and the demo draw.

#include <Eigen/Geometry>
#include <map>
#include <set>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/core/track_observation.h"

namespace omnisfm::sfm {

struct ObservationResidual {
  int frame = 0;
  int track = 0;
  Eigen::Vector2d pixel{0, 0};     // observed
  Eigen::Vector2d residual{0, 0};  // projected - observed
  bool outlier = false;            // the track is one of the rejected ones
};

// One entry per observation whose frame has a pose and whose track has a point that projects
// validly, in the order of `observations`; the others (no estimate, or no valid projection) are
// left out and counted in *left_out when it is given.
std::vector<ObservationResidual> reprojection_residuals(
    const camera::CatadioptricCamera& camera, const std::vector<core::TrackObservation>& observations,
    const std::vector<Eigen::Isometry3d>& world_from_cam,
    const std::map<int, Eigen::Vector3d>& points, const std::set<int>& outlier_tracks,
    int* left_out = nullptr);

}  // namespace omnisfm::sfm
