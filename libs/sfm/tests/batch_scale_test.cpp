// The batch's scale: measured on every run, kept free only where the images fix it, held (and
// said to be) where they do not, held at a known distance when one is given.

#include <gtest/gtest.h>

#include <limits>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/trajectories.h"
#include "filter_start.h"
#include "scale_runs.h"

namespace omnisfm::sfm {
namespace {

sim::Dataset simulated(const std::string& scenario, std::uint64_t seed) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.seed = seed;
  return sim::simulate(options);
}

double first_to_last(const std::vector<Eigen::Isometry3d>& world_from_cam) {
  return (world_from_cam.back().translation() - world_from_cam.front().translation()).norm();
}

// The case: the lab, seed 1, where the free batch ran to a trajectory 108 times too long.
// Its images fix the inverse scale only to 1.6 times its true value (the 6 m room is seen through
// a 5 cm mirror by a rig that does not rotate), so the batch holds the filter's scale.
TEST(BatchScale, LabHoldsTheScaleItsImagesCannotFix) {
  const sim::Dataset d = simulated("lab", 1);
  SfmSettings settings;
  settings.batch.covariances = false;
  SfmSettings free = settings;
  free.batch.max_free_scale_sigma = std::numeric_limits<double>::infinity();
  const SfmResult ran_away = run_sfm(d.camera, d.observations, free);
  ASSERT_EQ(ran_away.batch.scale_source, BatchScale::kFromImages);
  // Measured: 108x, reported as +- 17,600 %.
  EXPECT_GT(length_per_true_length(ran_away.batch.world_from_cam, d), 50);
  EXPECT_GT(ran_away.batch.scale_sigma_relative, 50);

  const SfmResult r = run_sfm(d.camera, d.observations, settings);
  ASSERT_TRUE(r.batch.converged) << r.batch.message;
  EXPECT_EQ(r.batch.scale_source, BatchScale::kHeldAtStart);
  EXPECT_GT(r.batch.scale_sigma_relative, 50);
  // At the filter's (1.19 measured for both) to 0.5 %.
  const double filter = length_per_true_length(r.online_world_from_cam, d);
  const auto errors =
      eval::trajectory_errors(r.batch.world_from_cam, d.world_from_cam, true);
  const auto free_errors =
      eval::trajectory_errors(ran_away.batch.world_from_cam, d.world_from_cam, true);
  std::printf("lab seed 1: free %.1fx (+- %.0f %%), held %.4fx (filter %.4fx, +- %.0f %%); "
              "translation %.4f %% against %.4f %%, rotation spread %.4f against %.4f deg\n",
              length_per_true_length(ran_away.batch.world_from_cam, d),
              100 * ran_away.batch.scale_sigma_relative,
              length_per_true_length(r.batch.world_from_cam, d), filter,
              100 * r.batch.scale_sigma_relative, errors.translation_error_percent,
              free_errors.translation_error_percent, errors.rotation_spread_deg,
              free_errors.rotation_spread_deg);
  EXPECT_NEAR(length_per_true_length(r.batch.world_from_cam, d) / filter, 1, 0.005);
  // The shape is as good as the free batch's (measured 0.028 % both).
  EXPECT_LT(errors.translation_error_percent, 0.05);
  EXPECT_LT(errors.rotation_spread_deg, 0.05);
}

// A few seeds of each experiment; batch_scale_sweep_test.cpp runs 25 (CTest label `long`).
// Measured over seeds 1-3: lab and crane held (their images fix the scale to +-105-17,600 %),
// the rover free at +-9-10 %, 0.97-1.43 sigma from the truth.
TEST(BatchScale, SeedsWithinAFactorTwoOfTheTruthOrHeld) {
  std::vector<ScaleRun> runs;
  for (const char* scenario : {"lab", "crane", "rover"})
    for (std::uint64_t seed = 1; seed <= 3; ++seed) runs.push_back(scale_run(scenario, seed));
  expect_within_a_factor_two_or_held(runs);
  // Three free rover runs: none beyond 3 sigma, error / sigma RMS within [0.3, 2].
  expect_honest_sigmas(runs, 3, 4, 0.3, 2);
}

// A known distance between the first and last cameras holds the scale there, even where the
// images fix it (the rover: +-10 %) and where they do not (the lab).
TEST(BatchScale, KnownDistanceHoldsTheScaleThere) {
  for (const char* scenario : {"lab", "rover"}) {
    const sim::Dataset d = simulated(scenario, 1);
    SfmSettings settings;
    settings.batch.covariances = false;
    settings.batch.known_distance_m = first_to_last(d.world_from_cam);
    const SfmResult r = run_sfm(d.camera, d.observations, settings);
    ASSERT_TRUE(r.batch.converged) << r.batch.message;
    EXPECT_EQ(r.batch.scale_source, BatchScale::kHeldAtKnownDistance) << scenario;
    // What the images alone would say is still reported.
    EXPECT_TRUE(std::isfinite(r.batch.scale_sigma_relative)) << scenario;
    std::printf("%s: known distance held to %.4f %%, scale %.4f %% off, images +- %.1f %%\n",
                scenario,
                100 * (first_to_last(r.batch.world_from_cam) /
                           settings.batch.known_distance_m - 1),
                100 * (length_per_true_length(r.batch.world_from_cam, d) - 1),
                100 * r.batch.scale_sigma_relative);
    // Measured: the distance within 0.007 %, the scale within 0.04 % (lab) and 0.03 % (rover).
    EXPECT_NEAR(first_to_last(r.batch.world_from_cam) / settings.batch.known_distance_m,
                1, 0.002)
        << scenario;
    EXPECT_NEAR(length_per_true_length(r.batch.world_from_cam, d), 1, 0.002) << scenario;
  }
}

FilterStart rover_start(int frames) { return filter_start("rover", 1, frames); }

// A known distance that cannot be one, or between cameras that coincide in the start, fails the
// batch with the reason instead of scaling the scene by infinity.
TEST(BatchScale, UnusableKnownDistanceFailsTheBatch) {
  const FilterStart s = rover_start(150);
  BatchSettings settings;
  settings.covariances = false;
  for (double bad : {-1.0, std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::quiet_NaN()}) {
    settings.known_distance_m = bad;
    const BatchResult r = batch_adjust(s.data.camera, s.inliers, s.online.online_world_from_cam,
                                       s.online.online_points, settings);
    EXPECT_FALSE(r.converged);
    EXPECT_TRUE(r.world_from_cam.empty());
    EXPECT_NE(r.message.find("must be a finite number of metres above 0"), std::string::npos)
        << r.message;
  }
  // The last camera moved back onto the first: a loop closed.
  std::vector<Eigen::Isometry3d> loop = s.online.online_world_from_cam;
  loop.back() = loop.front();
  settings.known_distance_m = 3;
  const BatchResult r =
      batch_adjust(s.data.camera, s.inliers, loop, s.online.online_points, settings);
  EXPECT_TRUE(r.world_from_cam.empty());
  EXPECT_NE(r.message.find("too close"), std::string::npos) << r.message;
}

// The rover's first 15 frames (0.37 m of its path) fix the scale only to +-54 %: held, and said so,
// where the whole sequence fixes it to +-10 %.
TEST(BatchScale, ShortSequenceIsHeld) {
  const FilterStart s = rover_start(15);
  BatchSettings settings;
  settings.covariances = false;
  const BatchResult r = batch_adjust(s.data.camera, s.inliers, s.online.online_world_from_cam,
                                     s.online.online_points, settings);
  ASSERT_TRUE(r.converged) << r.message;
  std::printf("rover, 15 frames (%.3f m): +- %.0f %%\n",
              sim::path_length(s.data.world_from_cam), 100 * r.scale_sigma_relative);
  EXPECT_EQ(r.scale_source, BatchScale::kHeldAtStart);
  EXPECT_GT(r.scale_sigma_relative, kMaxFreeScaleSigma);
}

// A start turning on the spot has no scale: said so, and none measured.
TEST(BatchScale, NoTranslationHasNoScale) {
  const FilterStart s = rover_start(150);
  // The filter's first camera is the world's origin; every camera is put there.
  ASSERT_LT(s.online.online_world_from_cam.front().translation().norm(), 1e-12);
  std::vector<Eigen::Isometry3d> standing;
  for (const auto& T : s.online.online_world_from_cam) {
    Eigen::Isometry3d still = T;
    still.translation().setZero();
    standing.push_back(still);
  }
  BatchSettings settings;
  settings.covariances = false;
  settings.max_iterations = 1;
  const BatchResult r =
      batch_adjust(s.data.camera, s.inliers, standing, s.online.online_points, settings);
  EXPECT_EQ(r.scale_source, BatchScale::kNoTranslation);
  EXPECT_TRUE(std::isnan(r.scale_sigma_relative));
}

}  // namespace
}  // namespace omnisfm::sfm
