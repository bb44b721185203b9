#include "omnisfm/camera/pinhole_camera.h"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>

namespace omnisfm::camera {
namespace {

bool valid_intrinsics(const PinholeIntrinsics& k) {
  const double all[] = {k.fx, k.fy, k.cx, k.cy, k.k1, k.k2, k.p1, k.p2, k.k3};
  for (double v : all)
    if (!std::isfinite(v)) return false;
  return k.fx > 0 && k.fy > 0;
}

// Distorted normalized coordinates of (a, b) and their 2x2 Jacobian.
Eigen::Vector2d distort(const PinholeIntrinsics& k, double a, double b, Eigen::Matrix2d* J) {
  const double r2 = a * a + b * b;
  const double radial = 1 + r2 * (k.k1 + r2 * (k.k2 + r2 * k.k3));
  const Eigen::Vector2d d(a * radial + 2 * k.p1 * a * b + k.p2 * (r2 + 2 * a * a),
                          b * radial + k.p1 * (r2 + 2 * b * b) + 2 * k.p2 * a * b);
  if (J) {
    const double dradial = k.k1 + r2 * (2 * k.k2 + 3 * k.k3 * r2);  // d radial / d r2
    const double cross = 2 * a * b * dradial + 2 * k.p1 * a + 2 * k.p2 * b;
    *J << radial + 2 * a * a * dradial + 2 * k.p1 * b + 6 * k.p2 * a, cross, cross,
        radial + 2 * b * b * dradial + 6 * k.p1 * b + 2 * k.p2 * a;
  }
  return d;
}

}  // namespace

PinholeCamera::PinholeCamera(const PinholeIntrinsics& intrinsics) : k_(intrinsics) {
  if (!valid_intrinsics(k_)) throw std::invalid_argument("pinhole: need finite values, fx, fy > 0");
}

std::unique_ptr<InnerCamera> PinholeCamera::clone() const {
  return std::make_unique<PinholeCamera>(*this);
}

std::vector<std::string> PinholeCamera::param_names() const {
  return {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2", "k3"};
}

Eigen::VectorXd PinholeCamera::params() const {
  Eigen::VectorXd v(9);
  v << k_.fx, k_.fy, k_.cx, k_.cy, k_.k1, k_.k2, k_.p1, k_.p2, k_.k3;
  return v;
}

bool PinholeCamera::set_params(const Eigen::VectorXd& v) {
  if (v.size() != 9) return false;
  const PinholeIntrinsics k{v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8]};
  if (!valid_intrinsics(k)) return false;
  k_ = k;
  return true;
}

bool PinholeCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel,
                            Eigen::Matrix<double, 2, 3>* J_p, ParamsJacobian* J_params) const {
  if (!(p.z() > 0)) return false;
  const double iz = 1 / p.z();
  const double a = p.x() * iz, b = p.y() * iz;
  Eigen::Matrix2d J_d_ab;
  const Eigen::Vector2d d = distort(k_, a, b, J_p ? &J_d_ab : nullptr);
  *pixel << k_.fx * d.x() + k_.cx, k_.fy * d.y() + k_.cy;
  if (J_p) {
    Eigen::Matrix<double, 2, 3> J_ab_p;
    J_ab_p << iz, 0, -a * iz, 0, iz, -b * iz;
    *J_p = Eigen::DiagonalMatrix<double, 2>(k_.fx, k_.fy) * J_d_ab * J_ab_p;
  }
  if (J_params) {
    const double r2 = a * a + b * b;
    ParamsJacobian& J = *J_params;
    J.resize(2, 9);
    J << d.x(), 0, 1, 0, k_.fx * a * r2, k_.fx * a * r2 * r2, k_.fx * 2 * a * b,
        k_.fx * (r2 + 2 * a * a), k_.fx * a * r2 * r2 * r2,  //
        0, d.y(), 0, 1, k_.fy * b * r2, k_.fy * b * r2 * r2, k_.fy * (r2 + 2 * b * b),
        k_.fy * 2 * a * b, k_.fy * b * r2 * r2 * r2;
  }
  return true;
}

bool PinholeCamera::unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                              Eigen::Vector3d* direction) const {
  const Eigen::Vector2d target((pixel.x() - k_.cx) / k_.fx, (pixel.y() - k_.cy) / k_.fy);
  // Undistort by Newton's method from the distorted coordinates.
  Eigen::Vector2d ab = target;
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    Eigen::Matrix2d J;
    const Eigen::Vector2d residual = distort(k_, ab.x(), ab.y(), &J) - target;
    const Eigen::Vector2d step = J.inverse() * residual;
    if (!step.allFinite()) return false;
    ab -= step;
    converged = step.norm() < 1e-15 * (1 + ab.norm());
  }
  if (!converged) {
    // Accept a last step at the level of rounding error.
    if ((distort(k_, ab.x(), ab.y(), nullptr) - target).norm() > 1e-13 * (1 + ab.norm()))
      return false;
  }
  origin->setZero();
  *direction = Eigen::Vector3d(ab.x(), ab.y(), 1).normalized();
  return true;
}

}  // namespace omnisfm::camera
