#pragma once
// One track's point from its pixels with the camera poses known: the rays' closest point, then
// Gauss-Newton on the reprojection errors. The batch uses it to re-test the tracks the filter
// rejected against its own solution: a good track the filter rejected (its point entered with a
// depth it did not know yet) fits every pose, a track that slid to another feature does not.

#include <Eigen/Geometry>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::sfm {

struct TrackSighting {
  Eigen::Isometry3d cam_from_world;
  Eigen::Vector2d pixel;
};

struct TriangulatedTrack {
  bool valid = false;  // the rays cross (parallax) and the point projects into every sighting
  Eigen::Vector3d point{0, 0, 0};  // world
  double largest_residual_px = 0;
  double rms_px = 0;  // per coordinate
};

// At least two sightings are needed; rays within `min_parallax_rad` of parallel, or a point that
// does not project into every sighting at the end, give an invalid result.
TriangulatedTrack triangulate_track(const camera::CatadioptricCamera& camera,
                                    const std::vector<TrackSighting>& sightings,
                                    double min_parallax_rad = 1e-3);

}  // namespace omnisfm::sfm
