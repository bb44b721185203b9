#pragma once
// A pose of the camera with no guess from the user: the noncentral absolute pose (OpenGV's GP3P in
// RANSAC, then its GPnP on the inliers) of the camera's unprojected rays against the known points.

#include <Eigen/Geometry>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::calib {

// False when too few pixels unproject or no consistent pose is found.
bool initial_pose(const camera::CatadioptricCamera& camera,
                  const std::vector<Eigen::Vector3d>& points_object,
                  const std::vector<Eigen::Vector2d>& pixels, Eigen::Isometry3d* cam_from_object);

}  // namespace omnisfm::calib
