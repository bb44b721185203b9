#pragma once
// sin and cos of one angle together, inline: the projection's Newton loop needs both for a few
// angles per step, and the library's sincos costs several times this. Reduction by quarter turns
// (pi/2 in two parts, exact enough for the few radians the loop meets), then Taylor polynomials
// on [-pi/4, pi/4] whose truncation (below 1e-18) is far under rounding: about one unit in the last
// place, like the library. Angles beyond kMaxReducedAngle go to the library.

#include <cmath>

namespace omnisfm::camera {

// c[0] + c[1] x + ... + c[N-1] x^(N-1) by Horner's rule.
template <int N>
inline double polynomial(double x, const double (&c)[N]) {
  double result = c[N - 1];
  for (int i = N - 2; i >= 0; --i) result = result * x + c[i];
  return result;
}

inline void sin_cos(double x, double* sine, double* cosine) {
  constexpr double kMaxReducedAngle = 64.0;
  if (!(std::abs(x) <= kMaxReducedAngle)) {
    *sine = std::sin(x);
    *cosine = std::cos(x);
    return;
  }
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kHalfPiHigh = 1.5707963267948966192;        // pi/2 rounded to double
  constexpr double kHalfPiLow = 6.123233995736766036e-17;      // pi/2 - kHalfPiHigh
  const int quarter_turns = static_cast<int>(x * kTwoOverPi + (x >= 0 ? 0.5 : -0.5));
  const double r = (x - quarter_turns * kHalfPiHigh) - quarter_turns * kHalfPiLow;
  const double r2 = r * r;
  // sin r = r + r^3 (-1/3! + r^2/5! - ... + r^14/17!),
  // cos r = 1 - r^2/2 + r^4 (1/4! - r^2/6! + ... - r^14/18!).
  constexpr double kSinTail[] = {-1.0 / 6,          1.0 / 120,           -1.0 / 5040,
                                 1.0 / 362880,      -1.0 / 39916800,     1.0 / 6227020800,
                                 -1.0 / 1307674368000, 1.0 / 355687428096000};
  constexpr double kCosTail[] = {1.0 / 24,          -1.0 / 720,          1.0 / 40320,
                                 -1.0 / 3628800,    1.0 / 479001600,     -1.0 / 87178291200,
                                 1.0 / 20922789888000, -1.0 / 6402373705728000};
  const double sin_tail = r2 * polynomial(r2, kSinTail);
  const double cos_tail = r2 * r2 * polynomial(r2, kCosTail);
  const double s = r + r * sin_tail;
  const double c = (1 - 0.5 * r2) + cos_tail;
  switch (quarter_turns & 3) {
    case 0:
      *sine = s;
      *cosine = c;
      break;
    case 1:
      *sine = c;
      *cosine = -s;
      break;
    case 2:
      *sine = -s;
      *cosine = -c;
      break;
    default:
      *sine = -c;
      *cosine = s;
      break;
  }
}

}  // namespace omnisfm::camera
