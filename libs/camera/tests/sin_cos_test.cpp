// The projection's inline sin and cos against the standard library's.

#include "../src/sin_cos.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace omnisfm::camera {
namespace {

// Units in the last place of |reference| between value and reference.
double ulps(double value, double reference) {
  const double magnitude = std::max(std::abs(reference), std::numeric_limits<double>::min());
  const double ulp = std::nextafter(magnitude, INFINITY) - magnitude;
  return std::abs(value - reference) / ulp;
}

TEST(SinCos, WithinTwoUlpsOfTheLibraryOverTheReducedRange) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> wide(-64, 64), narrow(-1, 1);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double x = i % 2 ? wide(rng) : narrow(rng);
    double s, c;
    sin_cos(x, &s, &c);
    // The library's own error (below one ulp) adds to ours: allow two in all.
    worst = std::max({worst, ulps(s, std::sin(x)), ulps(c, std::cos(x))});
  }
  EXPECT_LE(worst, 2.0);
}

TEST(SinCos, ExactWhereTheAnswerIsExact) {
  double s, c;
  sin_cos(0.0, &s, &c);
  EXPECT_EQ(s, 0.0);
  EXPECT_EQ(c, 1.0);
  sin_cos(1e-300, &s, &c);
  EXPECT_EQ(s, 1e-300);
  EXPECT_EQ(c, 1.0);
}

TEST(SinCos, BeyondTheReducedRangeAndNonFiniteAsTheLibrary) {
  for (double x : {100.0, -1e6, 1e300}) {
    double s, c;
    sin_cos(x, &s, &c);
    EXPECT_EQ(s, std::sin(x)) << x;
    EXPECT_EQ(c, std::cos(x)) << x;
  }
  double s, c;
  sin_cos(NAN, &s, &c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
  sin_cos(INFINITY, &s, &c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

}  // namespace
}  // namespace omnisfm::camera
