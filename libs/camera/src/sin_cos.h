#pragma once
// sin and cos of one angle together, inline: the projection's Newton loop needs both for a few
// angles per step, and the library's sincos costs several times this. Reduction by quarter turns
// (pi/2 in two parts, accurate for the few radians the loop meets), then minimax polynomials
// on [-pi/4, pi/4]: within two units in the last place (the library: one). Angles beyond
// kMaxReducedAngle go to the library.

#include <cmath>

namespace omnisfm::camera {

inline void sin_cos(double x, double* sine, double* cosine) {
  constexpr double kMaxReducedAngle = 64.0;
  if (!(std::abs(x) <= kMaxReducedAngle)) {
    *sine = std::sin(x);
    *cosine = std::cos(x);
    return;
  }
  constexpr double kTwoOverPi = 0.63661977236758134308;
  // pi/2 in two parts as fdlibm's reduction has it: the first with 33 significant bits, so that
  // its product with the few quarter turns here is exact.
  constexpr double kHalfPiHigh = 1.57079632673412561417e+00;
  constexpr double kHalfPiLow = 6.07710050650619224932e-11;
  // Round to the nearest quarter turn by adding and removing 1.5 * 2^52, which leaves no bits
  // below the unit: shorter than a round trip through an integer register.
  constexpr double kRoundingShift = 6755399441055744.0;
  const double quarter_turns = (x * kTwoOverPi + kRoundingShift) - kRoundingShift;
  const double r = (x - quarter_turns * kHalfPiHigh) - quarter_turns * kHalfPiLow;
  // fdlibm's minimax polynomials (__kernel_sin, __kernel_cos), evaluated pairwise (Estrin) so
  // that the dependency chain stays short.
  const double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  const double sin_tail =
      r2 * ((-1.66666666666666324348e-01 + 8.33333333332248946124e-03 * r2) +
            r4 * (-1.98412698298579493134e-04 + 2.75573137070700676789e-06 * r2) +
            r8 * (-2.50507602534068634195e-08 + 1.58969099521155010221e-10 * r2));
  const double cos_tail =
      r4 * ((4.16666666666666019037e-02 - 1.38888888888741095749e-03 * r2) +
            r4 * (2.48015872894767294178e-05 - 2.75573143513906633035e-07 * r2) +
            r8 * (2.08757232129817482790e-09 - 1.13596475577881948265e-11 * r2));
  const double s = r + r * sin_tail;
  const double c = (1 - 0.5 * r2) + cos_tail;
  switch (static_cast<int>(quarter_turns) & 3) {
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
