#include "omnisfm/core/chi_square.h"

#include <gtest/gtest.h>

namespace omnisfm::core {
namespace {

TEST(ChiSquare, NormalQuantilesMatchTheTables) {
  EXPECT_NEAR(normal_upper_quantile(0.5), 0.0, 1e-9);
  EXPECT_NEAR(normal_upper_quantile(0.025), 1.959964, 1e-6);
  EXPECT_NEAR(normal_upper_quantile(1e-4), 3.719016, 1e-6);
  EXPECT_NEAR(normal_upper_quantile(0.975), -1.959964, 1e-6);
}

TEST(ChiSquare, QuantilesWithinTheStatedErrorOfTheTables) {
  // Exact values (scipy.stats.chi2.isf) and the approximation's stated error, which errs high.
  struct Row { double dof, tail, exact, error; };
  for (const Row& r : {Row{3, 1e-4, 21.108, 0.04}, Row{10, 1e-4, 35.564, 0.02},
                       Row{30, 1e-3, 59.703, 0.005}, Row{100, 1e-4, 161.319, 0.001},
                       Row{300, 1e-4, 399.756, 0.001}}) {
    const double q = chi_square_upper_quantile(r.dof, r.tail);
    EXPECT_GE(q, r.exact * (1 - 1e-4)) << r.dof << " " << r.tail;
    EXPECT_LE(q, r.exact * (1 + r.error)) << r.dof << " " << r.tail;
  }
  // At wide tails it errs low, by under 1 %.
  EXPECT_NEAR(chi_square_upper_quantile(2, 0.05), 5.991, 0.01 * 5.991);
}

}  // namespace
}  // namespace omnisfm::core
