#pragma once
// A shape-from-motion result as an MRPT 3D scene file (.3Dscene: a gzip-compressed, serialized
// mrpt::opengl::COpenGLScene, as SceneViewer3D opens it). Its objects, named so that a program
// can find them (COpenGLScene::getByName):
//   "trajectory"         CSetOfLines: the camera centres, frame to frame (blue)
//   "online_trajectory"  CSetOfLines: the online filter's (grey), when given
//   "cameras"            CSetOfObjects: an axis triad at every tenth camera pose (and the last)
//   "points"             CPointCloud: the 3D points
//   "point_uncertainty"  CSetOfObjects: one CEllipsoid3D per point with a covariance, drawn at
//                        `ellipsoid_sigmas` (its quantile), named "point <track>"
//   "ground"             CGridPlaneXY under the scene, 1 m cells
// Coordinates are the result's world frame, metres.
//
// MRPT-free: the omnisfm command calls this without MRPT headers.

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

namespace omnisfm::mrpt_plugin {

struct SceneContents {
  std::vector<Eigen::Isometry3d> world_from_cam;
  std::vector<Eigen::Isometry3d> online_world_from_cam;  // may be empty
  std::map<int, Eigen::Vector3d> points;
  std::map<int, Eigen::Matrix3d> point_covariances;  // for some or all of the points
  double ellipsoid_sigmas = 3;
};

// Writes the scene to `path`, replaced whole or not at all; throws std::runtime_error naming the
// file when it cannot.
void write_scene_file(const std::string& path, const SceneContents& scene);

}  // namespace omnisfm::mrpt_plugin
