#pragma once
// The rig's motion in the paper's three experiments, as world_from_cam poses (world: z up).

#include <Eigen/Geometry>
#include <vector>

namespace omnisfm::sim {

// The lab: the rig inverted (mirror below the camera, looking up) moving without rotating in a U
// along three edges of an optical bench at `height`: legs of 1.02, 2.04 and 1.02 m, 41 images.
std::vector<Eigen::Isometry3d> lab_trajectory(double height);

// The Robocrane: 140 images on a horizontal arc of radius `radius` about (0, 0, height), 3.08 m
// of travel, the rig's axis (camera below the mirror) kept through the ground point (0, 0, 0) by pitch
// and roll alone.
std::vector<Eigen::Isometry3d> crane_trajectory(double radius, double height);

// The rover: 150 images, 3.91 m of planar driving with yaw changes, the rig upright at `height`.
std::vector<Eigen::Isometry3d> rover_trajectory(double height);

// Distance travelled along a trajectory.
double path_length(const std::vector<Eigen::Isometry3d>& world_from_cam);

}  // namespace omnisfm::sim
