// The refined camera's published covariance against its actual errors, over rover seeds 1-8
// (1-20 with OMNISFM_TEST_SIZE=full, about 2 minutes; CTest label `long`): each seed's rig moved by
// a draw from the target calibration's covariance (imperfect_calibration.h), then refined by the
// batch. `build/bench/ calibration_error_cost` prints the whole table, lab and crane too.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "imperfect_calibration.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/eval/calibration_error.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "test_size.h"

namespace omnisfm::sfm {
namespace {

// Measured: refined on 15 of the 20 seeds (2, 9, 15, 18 and 20 hold the scale, and the camera
// with it); over those the NEES (5 parameters: 5 when honest) 1.7-11.6, mean 6.1, and the
// batch's translation error at most 1.37x the exact camera's, median 1.07x (unrefined up to
// 2.45x, median 1.4x). Seeds 1-8: refined on 7, mean NEES 7.85, median ratio 1.04, worst 1.36.
TEST(CameraRefinementSweep, RefinedCamerasNearTheTruthWithHonestCovariances) {
  const std::uint64_t num_seeds = small_or_full<std::uint64_t>(8, 20);
  std::vector<double> nees, ratios;
  int held = 0;
  for (std::uint64_t seed = 1; seed <= num_seeds; ++seed) {
    sim::SimulationOptions options;
    options.scenario = "rover";
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    const CameraPrior prior = lab_target_calibration_prior(d.camera);
    SfmSettings settings;
    settings.batch.camera_prior = prior;
    const camera::CatadioptricCamera calibrated =
        eval::calibrated_with_error(d.camera, prior, 1000 + seed);
    const SfmResult refined = run_sfm(calibrated, d.observations, settings);
    if (refined.batch.scale_source == BatchScale::kHeldAtStart) {
      EXPECT_FALSE(refined.batch.camera_refined) << seed;
      ++held;
      continue;
    }
    ASSERT_TRUE(refined.batch.camera_refined) << seed;
    ASSERT_EQ(refined.batch.camera_covariance.rows(), 5) << seed;
    nees.push_back(std::pow(eval::sigmas_from_truth(refined.batch.camera_params, d.camera, prior,
                                              refined.batch.camera_covariance),
                            2));
    const SfmResult exact = run_sfm(d.camera, d.observations, SfmSettings());
    const auto error = [&](const SfmResult& r) {
      return eval::trajectory_errors(r.batch.world_from_cam, d.world_from_cam, true)
          .translation_error_percent;
    };
    ratios.push_back(error(refined) / error(exact));
  }
  ASSERT_GE(5 * nees.size(), 3 * num_seeds);  // refined on at least 60 % of the seeds
  EXPECT_EQ(held + static_cast<int>(nees.size()), static_cast<int>(num_seeds));
  double mean = 0;
  for (double n : nees) mean += n / static_cast<double>(nees.size());
  // The mean of n chi-square(5) draws is 5 +- sqrt(10 / n) when the covariance is honest: within
  // 3 of its standard deviations (15 draws: 2.55-7.45).
  const double spread = 3 * std::sqrt(10.0 / static_cast<double>(nees.size()));
  EXPECT_GT(mean, 5 - spread);
  EXPECT_LT(mean, 5 + spread);
  std::sort(ratios.begin(), ratios.end());
  EXPECT_LT(core::percentile(ratios, 0.5), 1.1);
  EXPECT_LT(ratios.back(), 1.5);
  std::printf(
      "refined on %zu of %d seeds: mean NEES %.2f, translation error / exact camera's "
      "median %.2f, worst %.2f\n",
      nees.size(), static_cast<int>(num_seeds), mean, core::percentile(ratios, 0.5), ratios.back());
}

}  // namespace
}  // namespace omnisfm::sfm
