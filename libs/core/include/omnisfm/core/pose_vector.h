#pragma once
// A rigid transform as the solvers hold it, six numbers: the rotation as an angle-axis vector
// (Ceres' convention), then the translation: X' = R(aa) X + t.

#include <ceres/rotation.h>

#include <Eigen/Geometry>

namespace omnisfm::core {

using PoseVector = Eigen::Matrix<double, 6, 1>;

inline PoseVector pose_vector_of(const Eigen::Isometry3d& T) {
  PoseVector v;
  const Eigen::Matrix3d R = T.linear();
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(R.data()), v.data());
  v.tail<3>() = T.translation();
  return v;
}

// The transform of the six numbers at `v`.
inline Eigen::Isometry3d isometry_of(const double* v) {
  Eigen::Matrix3d R;
  ceres::AngleAxisToRotationMatrix(v, ceres::ColumnMajorAdapter3x3(R.data()));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = Eigen::Map<const Eigen::Vector3d>(v + 3);
  return T;
}

inline Eigen::Isometry3d isometry_of(const PoseVector& v) { return isometry_of(v.data()); }

}  // namespace omnisfm::core
