#include "omnisfm/camera/conic_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace omnisfm::camera {
namespace {

// Keep the solver a little inside the edge of an ellipsoid, where the slope becomes infinite.
constexpr double kDomainFraction = 0.995;

double domain_max(double c, double kappa) {
  const double K = 1 + kappa;
  return K > 0 ? 1.0 / (c * std::sqrt(K)) : std::numeric_limits<double>::infinity();
}

}  // namespace

ConicProfile::ConicProfile(double z0, double c, double kappa, double rho_min, double rho_max)
    : z0_(z0), c_(c), kappa_(kappa) {
  if (!std::isfinite(z0) || !std::isfinite(kappa) || !std::isfinite(c) || c <= 0)
    throw std::invalid_argument("conic: need c > 0 and finite z0, kappa");
  if (!set_valid_range(rho_min, rho_max))
    throw std::invalid_argument("conic: need 0 <= rho_min < rho_max inside the conic's domain");
}

std::unique_ptr<MirrorProfile> ConicProfile::clone() const {
  return std::make_unique<ConicProfile>(*this);
}

std::vector<std::string> ConicProfile::shape_param_names() const {
  return {"conic_z0", "conic_c", "conic_kappa"};
}

Eigen::VectorXd ConicProfile::shape_params() const { return Eigen::Vector3d(z0_, c_, kappa_); }

bool ConicProfile::valid_shape(double z0, double c, double kappa, double rho_max) const {
  return std::isfinite(z0) && std::isfinite(c) && std::isfinite(kappa) && c > 0 &&
         rho_max < kDomainFraction * domain_max(c, kappa);
}

bool ConicProfile::set_shape_params(const Eigen::VectorXd& params) {
  if (params.size() != 3 || !valid_shape(params[0], params[1], params[2], s_max_)) return false;
  z0_ = params[0];
  c_ = params[1];
  kappa_ = params[2];
  return true;
}

bool ConicProfile::set_valid_range(double s_min, double s_max) {
  if (!(s_min >= 0 && s_min < s_max && s_max < kDomainFraction * domain_max(c_, kappa_)))
    return false;
  s_min_ = s_min;
  s_max_ = s_max;
  return true;
}

double ConicProfile::rho_domain_max() const { return domain_max(c_, kappa_); }

void ConicProfile::solve_domain(double* lo, double* hi) const {
  *hi = std::min(kDomainFraction * rho_domain_max(), s_max_ + 0.5 * (s_max_ - s_min_));
  *lo = -*hi;
}

void ConicProfile::evaluate(double rho, MeridianPoint* p, MeridianShapeJacobian* J_shape) const {
  const double K = 1 + kappa_;
  const double S = std::sqrt(1 - K * c_ * c_ * rho * rho);
  p->rho = rho;
  p->z = z0_ + c_ * rho * rho / (1 + S);
  p->drho = 1;
  p->dz = c_ * rho / S;
  p->d2rho = 0;
  p->d2z = c_ / (S * S * S);
  if (J_shape) {
    const double rho2 = rho * rho, S3 = S * S * S, onePlusS2 = (1 + S) * (1 + S);
    J_shape->setZero();
    J_shape->col(0) << 0, 1, 0, 0;
    J_shape->col(1) << 0, rho2 / (1 + S) + K * c_ * c_ * rho2 * rho2 / (S * onePlusS2), 0,
        rho / S + K * c_ * c_ * rho2 * rho / S3;
    J_shape->col(2) << 0, c_ * c_ * c_ * rho2 * rho2 / (2 * S * onePlusS2), 0,
        c_ * c_ * c_ * rho2 * rho / (2 * S3);
  }
}

double ConicProfile::implicit(double rho, double z, double* dG_drho, double* dG_dz) const {
  const double r = std::min(std::abs(rho), kDomainFraction * rho_domain_max());
  const double K = 1 + kappa_;
  const double S = std::sqrt(1 - K * c_ * c_ * r * r);
  const double f = z0_ + c_ * r * r / (1 + S);
  *dG_drho = r == std::abs(rho) ? -c_ * rho / S : 0.0;
  *dG_dz = 1;
  return z - f;
}

double ConicProfile::parameter_at(double rho, double) const { return rho; }

double ConicProfile::inner_focus_z() const {
  const double R = 1 / c_, K = 1 + kappa_;
  if (kappa_ >= 0) return std::numeric_limits<double>::quiet_NaN();
  if (K == 0) return z0_ + R / 2;
  const double A = R / std::abs(K), e = std::sqrt(-kappa_);
  return K < 0 ? z0_ + A * (e - 1) : z0_ + A * (1 - e);
}

double ConicProfile::outer_focus_z() const {
  const double R = 1 / c_, K = 1 + kappa_;
  if (K >= 0) return std::numeric_limits<double>::quiet_NaN();
  const double A = R / std::abs(K), e = std::sqrt(-kappa_);
  return z0_ - A * (1 + e);
}

}  // namespace omnisfm::camera
