#include "omnisfm/camera/table_profile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace omnisfm::camera {

TableProfile::TableProfile(std::vector<double> rho, std::vector<double> z, double rho_min,
                           double rho_max)
    : rho_(std::move(rho)), z_(std::move(z)) {
  const size_t n = rho_.size();
  if (n < 4 || z_.size() != n) throw std::invalid_argument("table: need at least 4 (rho, z) samples");
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(rho_[i]) || !std::isfinite(z_[i]))
      throw std::invalid_argument("table: samples must be finite");
    if (i > 0 && !(rho_[i] > rho_[i - 1]))
      throw std::invalid_argument("table: rho must be strictly increasing");
  }
  if (rho_.front() < 0) throw std::invalid_argument("table: rho must be >= 0");

  // Natural cubic spline: solve the tridiagonal system for the second derivatives.
  second_.assign(n, 0.0);
  std::vector<double> diag(n, 1.0), upper(n, 0.0), rhs(n, 0.0);
  for (size_t i = 1; i + 1 < n; ++i) {
    const double h0 = rho_[i] - rho_[i - 1], h1 = rho_[i + 1] - rho_[i];
    const double lower = h0 / 6;
    diag[i] = (h0 + h1) / 3;
    upper[i] = h1 / 6;
    rhs[i] = (z_[i + 1] - z_[i]) / h1 - (z_[i] - z_[i - 1]) / h0;
    // Forward elimination against row i-1 (row 0 is the natural boundary: second = 0).
    const double m = lower / diag[i - 1];
    diag[i] -= m * upper[i - 1];
    rhs[i] -= m * rhs[i - 1];
  }
  for (size_t i = n - 2; i >= 1; --i) second_[i] = (rhs[i] - upper[i] * second_[i + 1]) / diag[i];

  if (!set_valid_range(rho_min, rho_max))
    throw std::invalid_argument("table: the valid rho range must lie inside the table");
}

std::unique_ptr<MirrorProfile> TableProfile::clone() const {
  return std::make_unique<TableProfile>(*this);
}

bool TableProfile::set_valid_range(double s_min, double s_max) {
  if (!(s_min >= rho_.front() && s_min < s_max && s_max <= rho_.back())) return false;
  s_min_ = s_min;
  s_max_ = s_max;
  return true;
}

void TableProfile::solve_domain(double* lo, double* hi) const {
  *hi = rho_.back();
  *lo = -*hi;
}

void TableProfile::spline(double rho, double* z, double* dz, double* d2z) const {
  const size_t n = rho_.size();
  if (rho <= rho_.front() || rho >= rho_.back()) {
    // Linear beyond the table, with the end slope, so the surface stays C1.
    const bool low = rho <= rho_.front();
    const size_t i = low ? 0 : n - 2;
    const double h = rho_[i + 1] - rho_[i];
    const double slope = (z_[i + 1] - z_[i]) / h +
                         (low ? -h * (2 * second_[i] + second_[i + 1]) / 6
                              : h * (second_[i] + 2 * second_[i + 1]) / 6);
    const double x0 = low ? rho_.front() : rho_.back();
    const double z0 = low ? z_.front() : z_.back();
    *z = z0 + slope * (rho - x0);
    *dz = slope;
    *d2z = 0;
    return;
  }
  const size_t i = std::upper_bound(rho_.begin(), rho_.end(), rho) - rho_.begin() - 1;
  const double h = rho_[i + 1] - rho_[i];
  const double a = (rho_[i + 1] - rho) / h, b = (rho - rho_[i]) / h;
  const double m0 = second_[i], m1 = second_[i + 1];
  *z = a * z_[i] + b * z_[i + 1] + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6;
  *dz = (z_[i + 1] - z_[i]) / h - (3 * a * a - 1) * h * m0 / 6 + (3 * b * b - 1) * h * m1 / 6;
  *d2z = a * m0 + b * m1;
}

void TableProfile::evaluate(double rho, MeridianPoint* p, MeridianShapeJacobian* J_shape) const {
  p->rho = rho;
  p->drho = 1;
  p->d2rho = 0;
  // Mirrored through the axis: z is even in rho.
  spline(std::abs(rho), &p->z, &p->dz, &p->d2z);
  if (rho < 0) p->dz = -p->dz;
  if (J_shape) J_shape->setZero();
}

double TableProfile::implicit(double rho, double z, double* dG_drho, double* dG_dz) const {
  double f, df, d2f;
  spline(std::abs(rho), &f, &df, &d2f);
  *dG_drho = rho >= 0 ? -df : df;
  *dG_dz = 1;
  return z - f;
}

double TableProfile::parameter_at(double rho, double) const { return rho; }

}  // namespace omnisfm::camera
