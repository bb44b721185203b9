// The refined camera's published covariance against its actual errors, over rover seeds 1-10
// (CTest label `long`, about 15 s): each seed's rig moved by a draw from the target calibration's
// covariance (imperfect_calibration.h), then refined by the batch. `build/bench/
// calibration_error_cost` prints the whole table, lab and crane too.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "imperfect_calibration.h"
#include "omnisfm/eval/calibration_error.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "world_from_cam.h"

namespace omnisfm::sfm {
namespace {

// Measured: refined on 8 of the 10 seeds (2 and 9 hold the scale, and the camera with it); over
// those the NEES (5 parameters: 5 when honest) 2.9-11.6, mean 7.2, and the batch's translation
// error 1.00-1.10x the exact camera's but seed 3's 1.37x (0.98-2.45x unrefined, median 1.36).
TEST(CameraRefinementSweep, RefinedCamerasNearTheTruthAndTheirCovariancesNearlyHonest) {
  std::vector<double> nees, ratios;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    sim::SimulationOptions options;
    options.scenario = "rover";
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    const BatchSettings::CameraPrior prior = lab_target_calibration_prior(d.camera);
    SfmSettings settings;
    settings.batch.camera_prior = prior;
    const camera::CatadioptricCamera calibrated =
        eval::calibrated_with_error(d.camera, prior, 1000 + seed);
    const SfmResult refined = run_sfm(calibrated, d.observations, settings);
    if (refined.batch.scale_source == BatchScale::kHeldAtStart) continue;
    ASSERT_EQ(refined.batch.camera_covariance.rows(), 5) << seed;
    nees.push_back(std::pow(eval::sigmas_from_truth(refined.batch.camera_params, d.camera, prior,
                                              refined.batch.camera_covariance),
                            2));
    const SfmResult exact = run_sfm(d.camera, d.observations, SfmSettings());
    const auto error = [&](const SfmResult& r) {
      return eval::trajectory_errors(inverted(r.batch.cam_from_world), d.world_from_cam, true)
          .translation_error_percent;
    };
    ratios.push_back(error(refined) / error(exact));
  }
  ASSERT_GE(nees.size(), 6u);
  double mean = 0;
  for (double n : nees) mean += n / nees.size();
  // The mean of 8 chi-square(5) draws is 5 +- 1.1. Measured 7.2: about 1.4 times overconfident
  // in variance; the bound allows 1.8.
  EXPECT_GT(mean, 2.5);
  EXPECT_LT(mean, 9);
  std::sort(ratios.begin(), ratios.end());
  EXPECT_LT(ratios[(ratios.size() - 1) / 2], 1.1);
  EXPECT_LT(ratios.back(), 1.5);
  std::printf("refined on %zu of 10 seeds: mean NEES %.2f, translation error / exact camera's "
              "median %.2f, worst %.2f\n",
              nees.size(), mean, ratios[(ratios.size() - 1) / 2], ratios.back());
}

}  // namespace
}  // namespace omnisfm::sfm
