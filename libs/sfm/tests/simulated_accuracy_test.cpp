// The pipeline on the simulated experiments: the filter and the batch adjustment against ground
// truth, with the paper's error figures.

#include <gtest/gtest.h>

#include <set>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sfm {
namespace {

struct PipelineRun {
  eval::TrajectoryErrors online, batch;
  eval::OutlierDetection outliers;
  eval::PointErrors points;
  SfmResult result;
};

PipelineRun run(const std::string& scenario, std::uint64_t seed,
                const SfmSettings& settings = SfmSettings()) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.seed = seed;
  const sim::Dataset d = sim::simulate(options);
  const std::vector<core::TrackObservation>& tracks = d.observations;
  PipelineRun r;
  r.result = run_sfm(d.camera, tracks, settings);
  r.online = eval::trajectory_errors(r.result.online_world_from_cam, d.world_from_cam, true);
  r.batch = eval::trajectory_errors(r.result.batch.world_from_cam, d.world_from_cam, true);
  std::set<int> detected, actual;
  for (const auto& o : r.result.outliers) detected.insert(o.track);
  for (const auto& o : d.outliers) actual.insert(o.track);
  r.outliers = eval::outlier_detection(detected, actual);
  std::map<int, Eigen::Vector3d> truth;
  for (size_t t = 0; t < d.track_points.size(); ++t)
    if (!actual.count(static_cast<int>(t))) truth[static_cast<int>(t)] = d.track_points[t];
  r.points = eval::point_errors(r.result.batch.points, truth, r.result.batch.world_from_cam,
                                d.world_from_cam, r.batch.alignment);
  std::printf("%s: online %.3f%% %.2f deg; batch %.3f%% %.2f deg (yaw %.2f, spread %.2f), "
              "%.4f m; depth %.2f%%; outliers %d/%d/%d; batch rms %.3f px %d it %.2f s (solve %.2f s)\n",
              scenario.c_str(), r.online.translation_error_percent, r.online.mean_rotation_error_deg,
              r.batch.translation_error_percent, r.batch.mean_rotation_error_deg,
              r.batch.mean_yaw_error_deg, r.batch.rotation_spread_deg,
              r.batch.mean_translation_error_m, r.points.mean_depth_error_percent,
              r.outliers.correct, r.outliers.detected, r.outliers.actual,
              r.result.batch.final_rms_px, r.result.batch.iterations, r.result.batch.seconds,
              r.result.batch.solve_seconds);
  return r;
}

TEST(SimulatedAccuracy, Rover) {
  const PipelineRun r = run("rover", 1);
  EXPECT_TRUE(r.result.batch.converged) << r.result.batch.message;
  EXPECT_LT(r.batch.translation_error_percent, 1.02);
  EXPECT_LT(r.batch.mean_yaw_error_deg, 0.48);
  EXPECT_GE(r.outliers.precision, 0.95);
  EXPECT_GE(r.outliers.recall, 0.95);
  // Vision alone the rover's scale is the images' to +-10 %, and the filter, whose points'
  // anchors are states, lets it move within that as the frames come: 0.022-0.029 % over seeds
  // 1-3 where the batch gives 0.013-0.015 %; 0.066-0.090 % while the state's origin stayed at
  // the first frame (FilterSettings::origin_follows_camera).
  EXPECT_LT(r.online.translation_error_percent, 0.04);
}

// Linearised once at the constant velocity (FilterSettings::linearise_at_constant_velocity) the
// filter keeps the scale its depth priors gave the map (below), here near the truth's, and its
// online error comes to the batch's: 0.013 % at seed 1 (0.023 % iterated, 0.023 % linearised
// once at the prediction, the classic EKF).
TEST(SimulatedAccuracy, RoverLinearisedAtTheConstantVelocity) {
  SfmSettings settings;
  settings.filter.linearise_at_constant_velocity = true;
  const PipelineRun r = run("rover", 1, settings);
  EXPECT_LT(r.online.translation_error_percent, 0.018);
  EXPECT_NEAR(1 / r.online.alignment.scale, 1, 0.1);
  EXPECT_GE(r.outliers.precision, 0.95);
  EXPECT_GE(r.outliers.recall, 0.95);
}

// Linearised at the constant velocity, the map keeps the scale the new points' depth priors give
// it (FilterSettings::initial_depth), which vision alone barely moves: on the rover (seed 1),
// whose points are about 2 m away, the map is 1.00 times the truth's at the default 2 m, 0.50 at
// 1 m and 1.88 at 4 m (iterated: 6.2, 2.7 and 7.4); on the lab and crane, at 2 m, 0.65 and 0.64.
TEST(SimulatedAccuracy, LinearisedAtTheConstantVelocityTheMapKeepsTheDepthPriorsScale) {
  for (const double depth : {1.0, 4.0}) {
    SfmSettings settings;
    settings.filter.linearise_at_constant_velocity = true;
    settings.filter.initial_depth = depth;
    const PipelineRun r = run("rover", 1, settings);
    const double map_scale = 1 / r.online.alignment.scale;
    EXPECT_NEAR(map_scale / (depth / 2), 1, 0.1) << depth << " m: the map " << map_scale;
  }
}

TEST(SimulatedAccuracy, Crane) {
  const PipelineRun r = run("crane", 1);
  EXPECT_TRUE(r.result.batch.converged) << r.result.batch.message;
  EXPECT_LT(r.batch.translation_error_percent, 0.79);
  EXPECT_LT(r.batch.mean_rotation_error_deg, 1.61);
  EXPECT_GE(r.outliers.precision, 0.95);
  EXPECT_GE(r.outliers.recall, 0.95);
  EXPECT_LT(r.online.translation_error_percent, 2 * r.batch.translation_error_percent);
}

TEST(SimulatedAccuracy, Lab) {
  const PipelineRun r = run("lab", 1);
  EXPECT_TRUE(r.result.batch.converged) << r.result.batch.message;
  EXPECT_LT(r.batch.translation_error_percent, 0.12);
  EXPECT_LT(r.batch.rotation_spread_deg, 0.40);
  EXPECT_LT(r.online.translation_error_percent, 2 * r.batch.translation_error_percent);
}

// A sequence shorter than the smoothed start asked for is smoothed whole at its end: the lab's 41
// frames asked for 42 are estimated as when asked for 41 (without it, 1.3 % off for 0.03 %).
TEST(SimulatedAccuracy, ASequenceShorterThanItsSmoothedStartIsSmoothedWhole) {
  sim::SimulationOptions options;
  options.scenario = "lab";
  const sim::Dataset d = sim::simulate(options);
  const int frames = static_cast<int>(d.world_from_cam.size());
  SfmSettings settings;
  settings.run_batch = false;
  settings.filter.smoothed_start_frames = frames;
  const SfmResult whole = run_sfm(d.camera, d.observations, settings);
  settings.filter.smoothed_start_frames = frames + 1;
  const SfmResult longer = run_sfm(d.camera, d.observations, settings);
  ASSERT_EQ(longer.online_world_from_cam.size(), whole.online_world_from_cam.size());
  for (int f = 0; f < frames; ++f)
    EXPECT_TRUE(longer.online_world_from_cam[f].isApprox(whole.online_world_from_cam[f], 1e-9))
        << f;
  const eval::TrajectoryErrors e =
      eval::trajectory_errors(longer.online_world_from_cam, d.world_from_cam, true);
  EXPECT_LT(e.translation_error_percent, 0.1);
}

// More tracks at once than the filter takes (FilterSettings::max_live_points, here 40 of the
// rover's 110): the filter holds what it can, the batch places the rest from its poses and finds
// exactly the outliers among them, at the figures of the whole filter (0.013 %, 0.007 deg yaw).
TEST(SimulatedAccuracy, TracksBeyondTheFiltersRoomArePlacedByTheBatch) {
  sim::SimulationOptions options;
  options.scenario = "rover";
  const sim::Dataset d = sim::simulate(options);
  SfmSettings settings;
  settings.filter.max_live_points = 40;
  const SfmResult result = run_sfm(d.camera, d.observations, settings);
  EXPECT_GT(result.not_in_filter, 50);
  EXPECT_GE(result.placed_by_triangulation, result.not_in_filter - 7);
  std::set<int> detected, actual;
  for (const auto& o : result.outliers) detected.insert(o.track);
  for (const auto& o : d.outliers) actual.insert(o.track);
  EXPECT_EQ(detected, actual);
  const eval::TrajectoryErrors batch =
      eval::trajectory_errors(result.batch.world_from_cam, d.world_from_cam, true);
  EXPECT_LT(batch.translation_error_percent, 0.02);
  EXPECT_LT(batch.mean_yaw_error_deg, 0.02);
  // Every track but the outliers is in the batch.
  EXPECT_EQ(result.batch.points.size() + actual.size(), d.track_points.size());
}

// A track seen in one frame only carries nothing: no point online or in the batch, and not an
// outlier (with the filter's points leaving it out, the batch had taken it for one the filter had
// no room for, failed to place it and listed it as an outlier).
TEST(SimulatedAccuracy, ATrackSeenOnceIsNeitherAPointNorAnOutlier) {
  sim::SimulationOptions options;
  options.scenario = "rover";
  sim::Dataset d = sim::simulate(options);
  const SfmResult clean = run_sfm(d.camera, d.observations, SfmSettings());
  const int once = 1000000;
  core::TrackObservation seen_once = d.observations.front();
  for (const auto& o : d.observations)
    if (o.frame == 60) seen_once = o;
  seen_once.track = once;
  seen_once.pixel += Eigen::Vector2d(3, 3);
  d.observations.push_back(seen_once);
  const SfmResult result = run_sfm(d.camera, d.observations, SfmSettings());
  EXPECT_EQ(result.outliers.size(), clean.outliers.size());
  EXPECT_EQ(result.not_in_filter, 0);
  EXPECT_FALSE(result.online_points.count(once));
  EXPECT_FALSE(result.batch.points.count(once));
  EXPECT_EQ(result.batch.points.size(), clean.batch.points.size());
}

// The filter alone rejects exactly the outlier tracks, none of the good tracks that enter
// mid-sequence with a depth known only to the prior (seeds where undamped Gauss-Newton steps on
// such tracks oscillated by tens of pixels).
TEST(SimulatedAccuracy, FilterRejectsExactlyTheOutliers) {
  for (const auto& [scenario, seed] :
       std::vector<std::pair<std::string, std::uint64_t>>{{"rover", 1}, {"rover", 3}, {"crane", 3}}) {
    sim::SimulationOptions options;
    options.scenario = scenario;
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    SfmSettings settings;
    settings.run_batch = false;
    const SfmResult result = run_sfm(d.camera, d.observations, settings);
    std::set<int> detected, actual;
    for (const auto& o : result.outliers) detected.insert(o.track);
    for (const auto& o : d.outliers) actual.insert(o.track);
    EXPECT_EQ(detected, actual) << scenario << " seed " << seed;
  }
}

std::set<int> detected_outliers(const SfmResult& result) {
  std::set<int> detected;
  for (const auto& o : result.outliers) detected.insert(o.track);
  return detected;
}

std::set<int> actual_outliers(const sim::Dataset& d) {
  std::set<int> actual;
  for (const auto& o : d.outliers) actual.insert(o.track);
  return actual;
}

// A filter whose test is far too tight (the paper's rule at 0.6 px, for noise of 0.2 px)
// rejects dozens of good tracks; the batch takes back every one its solution explains, and keeps
// the mistracks out.
TEST(SimulatedAccuracy, BatchTakesBackTheGoodTracksTheFilterRejected) {
  for (const auto& [scenario, seed] :
       std::vector<std::pair<std::string, std::uint64_t>>{{"rover", 2}, {"crane", 2}}) {
    sim::SimulationOptions options;
    options.scenario = scenario;
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    SfmSettings settings;
    settings.filter.outlier_test = OutlierTest::kPixels;
    settings.filter.outlier_threshold_px = 0.6;
    settings.batch_outlier_threshold_px = 2.0;
    const SfmResult result = run_sfm(d.camera, d.observations, settings);
    const std::set<int> actual = actual_outliers(d);
    std::printf("%s: %d taken back, %zu rejected\n", scenario.c_str(), result.taken_back,
                result.outliers.size());
    // Measured: rover 69 taken back, crane 6.
    EXPECT_GE(result.taken_back, 5) << scenario;
    EXPECT_EQ(detected_outliers(result), actual) << scenario << " seed " << seed;
  }
}

// At the noise stated, whatever it is: the chi-square test scales with it where a fixed 2 px
// rejects most good tracks at 1 px of noise. Rover and crane with 0.5 px, seeds 1-2.
TEST(SimulatedAccuracy, ChiSquareTestHoldsAtTheStatedNoise) {
  int correct = 0, detected = 0, actual = 0;
  for (const std::string scenario : {"rover", "crane"})
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      sim::SimulationOptions options;
      options.scenario = scenario;
      options.seed = seed;
      options.tracking_noise_px = 0.5;
      const sim::Dataset d = sim::simulate(options);
      SfmSettings settings;
      settings.filter.pixel_sigma = 0.5;
      const SfmResult result = run_sfm(d.camera, d.observations, settings);
      const eval::OutlierDetection o =
          eval::outlier_detection(detected_outliers(result), actual_outliers(d));
      correct += o.correct;
      detected += o.detected;
      actual += o.actual;
    }
  std::printf("0.5 px: %d detected, %d correct, %d actual\n", detected, correct, actual);
  // Measured: 34 of 34, none wrong.
  EXPECT_GE(correct, 0.95 * detected);
  EXPECT_GE(correct, 0.95 * actual);
}

TEST(SimulatedAccuracy, PureRotationIsRefused) {
  // The rover's rig turning on the spot: no parallax, so no structure.
  sim::Dataset d{"spin", sim::default_rig(1024, 768), {}, {}, {}, {}, {}, {}, {}, {}};
  for (int i = 0; i < 40; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() << 0, 0, 0.6;
    d.world_from_cam.push_back(T);
    d.timestamps.push_back(i);
  }
  std::mt19937_64 rng(3);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 60; ++i) {
    const double a = sim::uniform(rng, -M_PI, M_PI), r = sim::uniform(rng, 1.5, 5);
    points.emplace_back(r * std::cos(a), r * std::sin(a), 0.0);
  }
  sim::TrackSimulationOptions tracking;
  sim::simulate_tracks(points, tracking, rng, &d);
  ASSERT_GT(d.observations.size(), 1000u);
  try {
    run_sfm(d.camera, d.observations, SfmSettings());
    FAIL() << "pure rotation was not refused";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("degenerate motion"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace omnisfm::sfm
