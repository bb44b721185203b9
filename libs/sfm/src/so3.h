#pragma once
// Rotations as rotation vectors (angle-axis): the exponential and logarithm of SO(3) and their
// Jacobians, for the motion residuals' analytic derivatives.
//   Exp(w + d) ~= Exp(J_left(w) d) Exp(w) ~= Exp(w) Exp(J_right(w) d)
//   Log(R Exp(d)) ~= Log(R) + J_right(Log R)^-1 d

#include <Eigen/Geometry>
#include <cmath>

namespace omnisfm::sfm::so3 {

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

inline Eigen::Matrix3d exp(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity() + skew(w);
  return Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
}

inline Eigen::Vector3d log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// The left Jacobian; the right one is J_left(-w).
inline Eigen::Matrix3d left_jacobian(const Eigen::Vector3d& w) {
  const double a = w.norm();
  const Eigen::Matrix3d W = skew(w);
  if (a < 1e-6) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 6.0;
  return Eigen::Matrix3d::Identity() + (1 - std::cos(a)) / (a * a) * W +
         (a - std::sin(a)) / (a * a * a) * W * W;
}

inline Eigen::Matrix3d right_jacobian(const Eigen::Vector3d& w) { return left_jacobian(-w); }

inline Eigen::Matrix3d right_jacobian_inverse(const Eigen::Vector3d& w) {
  const double a = w.norm();
  const Eigen::Matrix3d W = skew(w);
  if (a < 1e-6) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 12.0;
  return Eigen::Matrix3d::Identity() + 0.5 * W +
         (1 / (a * a) - (1 + std::cos(a)) / (2 * a * std::sin(a))) * W * W;
}

}  // namespace omnisfm::sfm::so3
