#include "omnisfm/sim/trajectories.h"

#include <cmath>

namespace omnisfm::sim {
namespace {

Eigen::Isometry3d pose(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& position) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation;
  T.translation() = position;
  return T;
}

}  // namespace

std::vector<Eigen::Isometry3d> lab_trajectory(double height) {
  // Camera z (toward the mirror) points down; x along the world's x.
  Eigen::Matrix3d inverted;
  inverted << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  constexpr double kStep = 0.102;  // 40 steps: 10 + 20 + 10 = 4.08 m
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Vector3d position(0, 0, height);
  poses.push_back(pose(inverted, position));
  const Eigen::Vector3d legs[3] = {{0, kStep, 0}, {kStep, 0, 0}, {0, -kStep, 0}};
  const int steps[3] = {10, 20, 10};
  for (int leg = 0; leg < 3; ++leg)
    for (int i = 0; i < steps[leg]; ++i) {
      position += legs[leg];
      poses.push_back(pose(inverted, position));
    }
  return poses;
}

std::vector<Eigen::Isometry3d> crane_trajectory(double radius, double height) {
  constexpr int kImages = 140;
  constexpr double kLength = 3.08;
  // Equal chords between images that add up to the path length.
  const double step_angle = 2 * std::asin(kLength / (kImages - 1) / (2 * radius));
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < kImages; ++i) {
    const double a = step_angle * i;
    const Eigen::Vector3d position(radius * std::cos(a), radius * std::sin(a), height);
    // Axis from the gazed ground point up through the camera to the mirror: z_C = R e_z with
    // R = Ry(pitch) Rx(roll), no yaw.
    const Eigen::Vector3d axis = position.normalized();
    const double roll = std::asin(-axis.y());
    const double pitch = std::atan2(axis.x(), axis.z());
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    poses.push_back(pose(R, position));
  }
  return poses;
}

std::vector<Eigen::Isometry3d> rover_trajectory(double height) {
  constexpr int kImages = 150;
  constexpr double kLength = 3.91;
  const double step = kLength / (kImages - 1);
  std::vector<Eigen::Isometry3d> poses;
  Eigen::Vector3d position(0, 0, height);
  for (int i = 0; i < kImages; ++i) {
    // Heading swings left then right: an S through the courtyard.
    const double heading = 0.7 * std::sin(2 * M_PI * i / (kImages - 1));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    poses.push_back(pose(R, position));
    position += step * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
  }
  return poses;
}

double path_length(const std::vector<Eigen::Isometry3d>& world_from_cam) {
  double length = 0;
  for (size_t i = 1; i < world_from_cam.size(); ++i)
    length += (world_from_cam[i].translation() - world_from_cam[i - 1].translation()).norm();
  return length;
}

}  // namespace omnisfm::sim
