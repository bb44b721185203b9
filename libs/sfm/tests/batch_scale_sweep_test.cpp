// The batch's scale over seeds 1-10 of the lab, crane and rover (1-25 with OMNISFM_TEST_SIZE=full,
// 40 s; CTest label `long`): every batch within a factor 2 of the true scale or held, and the free
// scales' reported standard deviations honest. `build/bench/batch_scale_sweep` prints the table.

#include <gtest/gtest.h>

#include "scale_runs.h"
#include "test_size.h"

namespace omnisfm::sfm {
namespace {

// One test, as CTest runs each in a process of its own and the seeds are the work.
// Measured: the lab and crane held on every seed (their images fix the inverse scale only to
// 1.6 and 2 times its value: +-35 % to +-590,000 % where the free batch ran to), the rover free
// on every seed, at most 1.164x (16 %) from the truth. Its 25 free scales: |error| < 3 sigma in
// all but one in 20, error / sigma with an RMS within [0.7, 1.4] (for 25 Gaussian draws,
// 1 +- 0.14; measured 0.86-0.87, worst 1.51 sigma). Seeds 1-10: RMS10 (for 10 draws, 1 +- 0.22).
TEST(BatchScaleSweep, EveryBatchWithinAFactorTwoOfTheTruthOrHeldWithHonestSigmas) {
  const std::uint64_t num_seeds = small_or_full<std::uint64_t>(10, 25);
  std::vector<ScaleRun> runs;
  for (const char* scenario : {"lab", "crane", "rover"})
    for (std::uint64_t seed = 1; seed <= num_seeds; ++seed)
      runs.push_back(scale_run(scenario, seed));
  expect_within_a_factor_two_or_held(runs);
  const int rover_seeds = static_cast<int>(num_seeds);
  const double rms = full_size_checks() ? expect_honest_sigmas(runs, 20, 20, 0.7, 1.4)
                                        : expect_honest_sigmas(runs, rover_seeds - 2, 10, 0.6, 1.6);
  std::printf("free scales: error / sigma RMS %.2f\n", rms);
}

}  // namespace
}  // namespace omnisfm::sfm
