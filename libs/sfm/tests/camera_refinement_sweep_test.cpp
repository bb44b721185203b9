// The refined camera's published covariance against its actual errors, over rover seeds 1-20
// (CTest label `long`, about 90 s): each seed's rig moved by a draw from the target calibration's
// covariance (imperfect_calibration.h), then refined by the batch. `build/bench/
// calibration_error_cost` prints the whole table, lab and crane too.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "imperfect_calibration.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/eval/calibration_error.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {
namespace {

constexpr std::uint64_t kSeeds = 20;

// Measured: refined on 15 of the 20 seeds (2, 9, 15, 18 and 20 hold the scale, and the camera
// with it); over those the NEES (5 parameters: 5 when honest) 1.7-11.6, mean 6.1, and the
// batch's translation error at most 1.37x the exact camera's, median 1.07x (unrefined up to
// 2.45x, median 1.4x).
TEST(CameraRefinementSweep, RefinedCamerasNearTheTruthWithHonestCovariances) {
  std::vector<double> nees, ratios;
  int held = 0;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
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
  ASSERT_GE(nees.size(), 12u);
  EXPECT_EQ(held + static_cast<int>(nees.size()), static_cast<int>(kSeeds));
  double mean = 0;
  for (double n : nees) mean += n / static_cast<double>(nees.size());
  // The mean of 15 chi-square(5) draws is 5 +- 0.82 when the covariance is honest: within 3 of
  // its standard deviations.
  EXPECT_GT(mean, 2.5);
  EXPECT_LT(mean, 7.5);
  std::sort(ratios.begin(), ratios.end());
  EXPECT_LT(core::percentile(ratios, 0.5), 1.1);
  EXPECT_LT(ratios.back(), 1.5);
  std::printf("refined on %zu of %d seeds: mean NEES %.2f, translation error / exact camera's "
              "median %.2f, worst %.2f\n",
              nees.size(), static_cast<int>(kSeeds), mean, core::percentile(ratios, 0.5),
              ratios.back());
}

}  // namespace
}  // namespace omnisfm::sfm
