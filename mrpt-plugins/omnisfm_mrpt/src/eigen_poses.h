#pragma once
// Rigid transforms between Eigen (the estimators' type) and MRPT's CPose3D. Inside the plugin only.

#include <mrpt/math/CMatrixFixed.h>
#include <mrpt/math/wrap2pi.h>
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

// Whether two transforms are one pose, stored twice: within a micrometre and a microradian.
inline bool same_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  constexpr double kTolerance = 1e-6;
  return (a.translation() - b.translation()).norm() <= kTolerance &&
         Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() <= kTolerance;
}

// MRPT's parameters of a pose: x, y, z, yaw, pitch, roll (the order of its covariances).
inline Eigen::Matrix<double, 6, 1> mrpt_parameters_of(const mrpt::poses::CPose3D& p) {
  Eigen::Matrix<double, 6, 1> v;
  v << p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll();
  return v;
}

// d mrpt_parameters_of(pose(x)) / dx at x by central differences, the angles' differences
// wrapped: how the estimators carry a covariance into MRPT's parameters. The map is smooth away
// from pitch = +-90 degrees, and a step of 1e-6 leaves errors near 1e-10, far below any
// covariance they report.
template <int N, typename PoseOf>
Eigen::Matrix<double, 6, N> mrpt_parameters_jacobian(const PoseOf& pose,
                                                     const Eigen::Matrix<double, N, 1>& x) {
  constexpr double kStep = 1e-6;
  Eigen::Matrix<double, 6, N> J;
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> plus = x, minus = x;
    plus[i] += kStep;
    minus[i] -= kStep;
    Eigen::Matrix<double, 6, 1> d = mrpt_parameters_of(pose(plus)) - mrpt_parameters_of(pose(minus));
    for (int a = 3; a < 6; ++a) d[a] = mrpt::math::wrapToPi(d[a]);
    J.col(i) = d / (2 * kStep);
  }
  return J;
}

}  // namespace omnisfm::mrpt_plugin
