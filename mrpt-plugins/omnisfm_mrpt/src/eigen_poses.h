#pragma once
// Rigid transforms between Eigen (the estimators' type) and MRPT's CPose3D. Inside the plugin only.

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>

namespace omnisfm::mrpt_plugin {

inline Eigen::Isometry3d isometry_of(const mrpt::poses::CPose3D& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = pose.getRotationMatrix().asEigen();
  T.translation() = Eigen::Vector3d(pose.x(), pose.y(), pose.z());
  return T;
}

inline mrpt::poses::CPose3D pose_of(const Eigen::Isometry3d& T) {
  return mrpt::poses::CPose3D(mrpt::math::CMatrixDouble44(T.matrix()));
}

// MRPT's parameters of a pose: x, y, z, yaw, pitch, roll (the order of its covariances).
inline Eigen::Matrix<double, 6, 1> mrpt_parameters_of(const mrpt::poses::CPose3D& p) {
  Eigen::Matrix<double, 6, 1> v;
  v << p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll();
  return v;
}

}  // namespace omnisfm::mrpt_plugin
