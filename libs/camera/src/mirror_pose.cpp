#include "omnisfm/camera/mirror_pose.h"

#include <cmath>

namespace omnisfm::camera {
namespace {

Eigen::Matrix3d rot_x(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return (Eigen::Matrix3d() << 1, 0, 0, 0, c, -s, 0, s, c).finished();
}
Eigen::Matrix3d rot_y(double b) {
  const double c = std::cos(b), s = std::sin(b);
  return (Eigen::Matrix3d() << c, 0, s, 0, 1, 0, -s, 0, c).finished();
}
Eigen::Matrix3d rot_x_derivative(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return (Eigen::Matrix3d() << 0, 0, 0, 0, -s, -c, 0, c, -s).finished();
}
Eigen::Matrix3d rot_y_derivative(double b) {
  const double c = std::cos(b), s = std::sin(b);
  return (Eigen::Matrix3d() << -s, 0, c, 0, 0, 0, -c, 0, -s).finished();
}

}  // namespace

Eigen::Matrix3d MirrorPose::rotation() const { return rot_x(rx) * rot_y(ry); }

void MirrorPose::rotation_derivatives(Eigen::Matrix3d* dR_drx, Eigen::Matrix3d* dR_dry) const {
  *dR_drx = rot_x_derivative(rx) * rot_y(ry);
  *dR_dry = rot_x(rx) * rot_y_derivative(ry);
}

}  // namespace omnisfm::camera
