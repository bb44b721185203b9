#pragma once
// Chi-square quantiles for tests whose degrees of freedom vary (a whole track's residuals), where
// a table of a few quantiles does not serve.

#include <cmath>

namespace omnisfm::core {

// z such that a standard normal exceeds it with probability `tail` (0 < tail < 1), by bisection
// to the double's precision.
inline double normal_upper_quantile(double tail) {
  double low = -40, high = 40;
  for (int i = 0; i < 200 && high - low > 1e-12; ++i) {
    const double mid = (low + high) / 2;
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > tail ? low : high) = mid;
  }
  return (low + high) / 2;
}

// x such that a chi-square with `dof` degrees of freedom exceeds it with probability `tail`:
// Wilson and Hilferty's cube-root normal approximation. It errs high (the test stricter on
// rejecting) by under 4 % for dof >= 3 at tails of 1e-3 to 1e-4, and under 0.1 % beyond 100 dof;
// at tails of 0.05 it errs low by under 1 %.
inline double chi_square_upper_quantile(double dof, double tail) {
  const double a = 2 / (9 * dof);
  const double root = 1 - a + normal_upper_quantile(tail) * std::sqrt(a);
  return dof * root * root * root;
}

}  // namespace omnisfm::core
