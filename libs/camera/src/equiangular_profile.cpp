#include "omnisfm/camera/equiangular_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sin_cos.h"

namespace omnisfm::camera {
namespace {

// cos(k theta) must stay positive; keep the solver a little inside that pole.
constexpr double kDomainFraction = 0.995;

double theta_pole(double alpha) { return M_PI / (1.0 + alpha); }

}  // namespace

EquiangularProfile::EquiangularProfile(double alpha, double r0, double theta_min,
                                       double theta_max)
    : alpha_(alpha), r0_(r0) {
  if (!valid_shape(alpha, r0)) throw std::invalid_argument("equiangular: alpha and r0 must be > 0");
  if (!set_valid_range(theta_min, theta_max))
    throw std::invalid_argument("equiangular: need 0 <= theta_min < theta_max < pi/(1+alpha)");
}

bool EquiangularProfile::valid_shape(double alpha, double r0) {
  return std::isfinite(alpha) && std::isfinite(r0) && alpha > 0 && r0 > 0;
}

std::unique_ptr<MirrorProfile> EquiangularProfile::clone() const {
  return std::make_unique<EquiangularProfile>(*this);
}

std::vector<std::string> EquiangularProfile::shape_param_names() const {
  return {"equiangular_alpha", "equiangular_r0"};
}

Eigen::VectorXd EquiangularProfile::shape_params() const {
  return Eigen::Vector2d(alpha_, r0_);
}

bool EquiangularProfile::set_shape_params(const Eigen::VectorXd& params) {
  if (params.size() != 2 || !valid_shape(params[0], params[1])) return false;
  if (s_max_ >= kDomainFraction * theta_pole(params[0])) return false;
  alpha_ = params[0];
  r0_ = params[1];
  return true;
}

bool EquiangularProfile::set_valid_range(double s_min, double s_max) {
  if (!(s_min >= 0 && s_min < s_max && s_max < kDomainFraction * theta_pole(alpha_))) return false;
  s_min_ = s_min;
  s_max_ = s_max;
  return true;
}

void EquiangularProfile::solve_domain(double* lo, double* hi) const {
  *hi = std::min(kDomainFraction * theta_pole(alpha_), s_max_ + 0.5 * (s_max_ - s_min_));
  *lo = -*hi;
}

double EquiangularProfile::radius(double theta) const {
  const double k = 0.5 * (1 + alpha_);
  return r0_ * std::pow(std::cos(k * theta), -1.0 / k);
}

void EquiangularProfile::evaluate(double theta, MeridianPoint* p,
                                  MeridianShapeJacobian* J_shape) const {
  const double k = 0.5 * (1 + alpha_);
  double sk, ck, st, ct;
  sin_cos(k * theta, &sk, &ck);
  sin_cos(theta, &st, &ct);
  const double tk = sk / ck;
  // cos(k theta)^(-1/k) through its logarithm, which the shape derivative reuses.
  const double log_ck = std::log(ck);
  const double r = r0_ * std::exp(log_ck * (-1 / k));
  const double dr = r * tk;                         // dr/dtheta
  const double d2r = r * (tk * tk + k * (1 + tk * tk));

  p->rho = r * st;
  p->z = r * ct;
  p->drho = dr * st + r * ct;
  p->dz = dr * ct - r * st;
  p->d2rho = d2r * st + 2 * dr * ct - r * st;
  p->d2z = d2r * ct - 2 * dr * st - r * ct;

  if (J_shape) {
    // alpha enters through k = (1 + alpha)/2; r is proportional to r0.
    const double dr_dk = r * (log_ck / (k * k) + theta * tk / k);
    const double ddr_dk = dr_dk * tk + r * theta * (1 + tk * tk);
    J_shape->setZero();
    J_shape->col(0) << 0.5 * dr_dk * st, 0.5 * dr_dk * ct, 0.5 * (ddr_dk * st + dr_dk * ct),
        0.5 * (ddr_dk * ct - dr_dk * st);
    J_shape->col(1) << p->rho / r0_, p->z / r0_, p->drho / r0_, p->dz / r0_;
  }
}

double EquiangularProfile::implicit(double rho, double z, double* dG_drho, double* dG_dz) const {
  const double d2 = rho * rho + z * z;
  const double d = std::sqrt(d2);
  double theta = std::atan2(rho, z);
  const double cap = kDomainFraction * theta_pole(alpha_);
  const bool clamped = theta > cap || theta < 0;
  theta = std::clamp(theta, 0.0, cap);
  const double k = 0.5 * (1 + alpha_);
  const double ck = std::cos(k * theta);
  const double r = r0_ * std::pow(ck, -1.0 / k);
  const double dr = clamped ? 0.0 : r * std::sin(k * theta) / ck;
  if (d2 > 0) {
    *dG_drho = rho / d - dr * z / d2;
    *dG_dz = z / d + dr * rho / d2;
  } else {
    *dG_drho = 0;
    *dG_dz = -1;
  }
  return d - r;
}

double EquiangularProfile::parameter_at(double rho, double z) const { return std::atan2(rho, z); }

}  // namespace omnisfm::camera
