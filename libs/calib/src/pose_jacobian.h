#pragma once
// A rigid pose as Ceres holds it, angle-axis then translation: X' = R(aa) X + t, and the
// derivative of X' with respect to those 6 numbers.

#include <ceres/jet.h>
#include <ceres/rotation.h>

#include <Eigen/Geometry>

#include "omnisfm/core/pose_vector.h"

namespace omnisfm::calib {

inline Eigen::Vector3d transform_point(const double* pose, const Eigen::Vector3d& X,
                                       Eigen::Matrix<double, 3, 6>* J_pose) {
  if (!J_pose) {
    Eigen::Vector3d rotated;
    ceres::AngleAxisRotatePoint(pose, X.data(), rotated.data());
    return rotated + Eigen::Map<const Eigen::Vector3d>(pose + 3);
  }
  using Jet = ceres::Jet<double, 6>;
  Jet p[6], x[3] = {Jet(X.x()), Jet(X.y()), Jet(X.z())}, out[3];
  for (int i = 0; i < 6; ++i) p[i] = Jet(pose[i], i);
  ceres::AngleAxisRotatePoint(p, x, out);
  Eigen::Vector3d result;
  for (int r = 0; r < 3; ++r) {
    out[r] += p[3 + r];
    result[r] = out[r].a;
    J_pose->row(r) = out[r].v.transpose();
  }
  return result;
}

}  // namespace omnisfm::calib
