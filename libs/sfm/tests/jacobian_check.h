#pragma once
// A cost function's analytic Jacobians against central differences.

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace omnisfm::sfm {

// Every block's analytic Jacobian against central differences, to `tolerance` of its largest
// entry (relative) or absolutely below 1.
inline void expect_jacobians_match(const ceres::CostFunction& cost, std::vector<std::vector<double>> blocks,
                            double tolerance) {
  const int m = cost.num_residuals();
  const auto& sizes = cost.parameter_block_sizes();
  std::vector<const double*> pointers;
  for (auto& b : blocks) pointers.push_back(b.data());
  std::vector<std::vector<double>> analytic(blocks.size());
  std::vector<double*> jacobian_pointers;
  for (size_t b = 0; b < blocks.size(); ++b) {
    analytic[b].resize(m * sizes[b]);
    jacobian_pointers.push_back(analytic[b].data());
  }
  std::vector<double> r(m), plus(m), minus(m);
  ASSERT_TRUE(cost.Evaluate(pointers.data(), r.data(), jacobian_pointers.data()));
  const double h = 1e-6;
  for (size_t b = 0; b < blocks.size(); ++b) {
    double scale = 1;
    for (double v : analytic[b]) scale = std::max(scale, std::abs(v));
    for (int j = 0; j < sizes[b]; ++j) {
      const double saved = blocks[b][j];
      blocks[b][j] = saved + h;
      ASSERT_TRUE(cost.Evaluate(pointers.data(), plus.data(), nullptr));
      blocks[b][j] = saved - h;
      ASSERT_TRUE(cost.Evaluate(pointers.data(), minus.data(), nullptr));
      blocks[b][j] = saved;
      for (int i = 0; i < m; ++i)
        EXPECT_NEAR(analytic[b][i * sizes[b] + j], (plus[i] - minus[i]) / (2 * h), tolerance * scale)
            << "block " << b << " residual " << i << " parameter " << j;
    }
  }
}

}  // namespace omnisfm::sfm
