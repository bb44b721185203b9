#include "omnisfm/camera/orthographic_camera.h"

#include <cmath>
#include <stdexcept>

namespace omnisfm::camera {
namespace {

bool valid_intrinsics(const OrthographicIntrinsics& k) {
  return std::isfinite(k.cx) && std::isfinite(k.cy) && std::isfinite(k.fx) &&
         std::isfinite(k.fy) && k.fx > 0 && k.fy > 0;
}

}  // namespace

OrthographicCamera::OrthographicCamera(const OrthographicIntrinsics& intrinsics) : k_(intrinsics) {
  if (!valid_intrinsics(k_))
    throw std::invalid_argument("orthographic: need finite values, fx, fy > 0");
}

std::unique_ptr<InnerCamera> OrthographicCamera::clone() const {
  return std::make_unique<OrthographicCamera>(*this);
}

std::vector<std::string> OrthographicCamera::param_names() const {
  return {"fx", "fy", "cx", "cy"};
}

Eigen::VectorXd OrthographicCamera::params() const {
  return Eigen::Vector4d(k_.fx, k_.fy, k_.cx, k_.cy);
}

bool OrthographicCamera::set_params(const Eigen::VectorXd& v) {
  if (v.size() != 4) return false;
  const OrthographicIntrinsics k{v[0], v[1], v[2], v[3]};
  if (!valid_intrinsics(k)) return false;
  k_ = k;
  return true;
}

bool OrthographicCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel,
                                 Eigen::Matrix<double, 2, 3>* J_p, ParamsJacobian* J_params) const {
  if (!p.allFinite()) return false;
  *pixel << k_.fx * p.x() + k_.cx, k_.fy * p.y() + k_.cy;
  if (J_p) *J_p << k_.fx, 0, 0, 0, k_.fy, 0;
  if (J_params) {
    ParamsJacobian& J = *J_params;
    J.resize(2, 4);
    J << p.x(), 0, 1, 0, 0, p.y(), 0, 1;
  }
  return true;
}

bool OrthographicCamera::unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                                   Eigen::Vector3d* direction) const {
  *origin << (pixel.x() - k_.cx) / k_.fx, (pixel.y() - k_.cy) / k_.fy, 0;
  *direction << 0, 0, 1;
  return origin->allFinite();
}

}  // namespace omnisfm::camera
