#include "omnisfm/sfm/reprojection_residuals.h"

namespace omnisfm::sfm {

std::vector<ObservationResidual> reprojection_residuals(
    const camera::CatadioptricCamera& camera, const std::vector<core::TrackObservation>& observations,
    const std::vector<Eigen::Isometry3d>& world_from_cam,
    const std::map<int, Eigen::Vector3d>& points, const std::set<int>& outlier_tracks,
    int* left_out) {
  std::vector<ObservationResidual> residuals;
  residuals.reserve(observations.size());
  int missing = 0;
  for (const core::TrackObservation& o : observations) {
    const auto point = points.find(o.track);
    Eigen::Vector2d projected;
    if (point == points.end() || o.frame < 0 ||
        o.frame >= static_cast<int>(world_from_cam.size()) ||
        !camera.project(world_from_cam[o.frame].inverse() * point->second, &projected)) {
      ++missing;
      continue;
    }
    residuals.push_back(
        {o.frame, o.track, o.pixel, projected - o.pixel, outlier_tracks.count(o.track) > 0});
  }
  if (left_out) *left_out = missing;
  return residuals;
}

}  // namespace omnisfm::sfm
