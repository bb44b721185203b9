#pragma once
// The 5-DOF mirror-to-camera transform (rotation about the mirror's axis changes nothing):
//   X_C = R(rx, ry) X_M + t,   R = Rx(rx) Ry(ry),   t = (tx, ty, tz).

#include <Eigen/Core>

namespace omnisfm::camera {

struct MirrorPose {
  double rx = 0, ry = 0;          // radians
  double tx = 0, ty = 0, tz = 0;  // metres

  // camera_from_mirror rotation R, and its derivatives with respect to rx and ry.
  Eigen::Matrix3d rotation() const;
  void rotation_derivatives(Eigen::Matrix3d* dR_drx, Eigen::Matrix3d* dR_dry) const;
  Eigen::Vector3d translation() const { return {tx, ty, tz}; }

  // Order of the 5 parameters wherever they appear as a vector: rx ry tx ty tz.
  Eigen::Matrix<double, 5, 1> as_vector() const { return {rx, ry, tx, ty, tz}; }
  static MirrorPose from_vector(const Eigen::Matrix<double, 5, 1>& v) {
    return {v[0], v[1], v[2], v[3], v[4]};
  }
};

}  // namespace omnisfm::camera
