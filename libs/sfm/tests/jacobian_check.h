#pragma once
// A cost function's analytic Jacobians against Ceres' own numeric differentiation
// (ceres::GradientChecker, Ridders' extrapolation).

#include <ceres/ceres.h>
#include <ceres/gradient_checker.h>
#include <gtest/gtest.h>

#include <vector>

namespace omnisfm::sfm {

// Every Jacobian entry within `relative_precision` of the numeric one (relative to the larger of
// the two; absolute where either is zero), at the parameter blocks `blocks`.
inline void expect_jacobians_match(const ceres::CostFunction& cost,
                                   const std::vector<std::vector<double>>& blocks,
                                   double relative_precision) {
  std::vector<const double*> pointers;
  for (const auto& b : blocks) pointers.push_back(b.data());
  // Ridders' first step is 1e-2 of each parameter by default, off the mirror for a projection.
  ceres::NumericDiffOptions options;
  options.ridders_relative_initial_step_size = 1e-4;
  const ceres::GradientChecker checker(
      &cost, static_cast<const std::vector<const ceres::Manifold*>*>(nullptr), options);
  ceres::GradientChecker::ProbeResults results;
  EXPECT_TRUE(checker.Probe(pointers.data(), relative_precision, &results)) << results.error_log;
}

}  // namespace omnisfm::sfm
