// The batch's scale over seeds 1-25 of the lab, crane and rover (CTest label `long`, 40 s on
// two cores): every batch within a factor 2 of the true scale or held, and the free
// scales' reported standard deviations honest. `build/bench/batch_scale_sweep` prints the table.

#include <gtest/gtest.h>

#include "scale_runs.h"

namespace omnisfm::sfm {
namespace {

constexpr std::uint64_t kSeeds = 25;

// One test, as CTest runs each in a process of its own and the seeds are the work.
// Measured: the lab and crane held on every seed (their images fix the inverse scale only to
// 1.6 and 2 times its value: +-35 % to +-590,000 % where the free batch ran to), the rover free
// on every seed, at most 1.164x (16 %) from the truth. Its 25 free scales: |error| < 3 sigma in
// all but one in 20, error / sigma with an RMS within [0.7, 1.4] (for 25 Gaussian draws,
// 1 +- 0.14; measured 0.86-0.87, worst 1.51 sigma).
TEST(BatchScaleSweep, EveryBatchWithinAFactorTwoOfTheTruthOrHeldWithHonestSigmas) {
  std::vector<ScaleRun> runs;
  for (const char* scenario : {"lab", "crane", "rover"})
    for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) runs.push_back(scale_run(scenario, seed));
  expect_within_a_factor_two_or_held(runs);
  const double rms = expect_honest_sigmas(runs, 20, 20, 0.7, 1.4);
  std::printf("free scales: error / sigma RMS %.2f\n", rms);
}

}  // namespace
}  // namespace omnisfm::sfm
