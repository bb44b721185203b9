// The batch re-tests the tracks against its solution only when that solution fits them: a solve
// left far from a fit (a start too far off) would reject good tracks by the hundred.

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "../src/pipeline_steps.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {
namespace {

struct Rover {
  sim::Dataset data;
  SfmSettings settings;
  SfmResult filtered;  // the filter's estimate, no batch yet
  std::vector<Eigen::Isometry3d> online_cam_from_world;
};

Rover rover_filtered() {
  sim::SimulationOptions options;
  options.scenario = "rover";
  options.seed = 1;
  Rover r{sim::simulate(options), SfmSettings(), SfmResult(), {}};
  r.online_cam_from_world = run_filter(r.data.camera, observations_by_frame(r.data.observations),
                                       r.settings.filter, nullptr, {}, &r.filtered);
  return r;
}

TEST(BatchRetest, ASolutionThatDoesNotFitTheTracksRejectsNone) {
  const Rover r = rover_filtered();
  SfmSettings settings = r.settings;
  settings.batch.max_iterations = 1;  // stopped far from a fit
  SfmResult result = r.filtered;
  // Every point three times as far from the first camera as the filter has it.
  const Eigen::Vector3d first = result.online_world_from_cam[0].translation();
  for (auto& [track, point] : result.online_points) point = first + 3 * (point - first);
  const std::size_t filter_outliers = result.outliers.size();
  adjust_on_inliers(r.data.camera, r.data.observations, settings, r.online_cam_from_world, nullptr,
                    &result);

  EXPECT_GT(result.batch.final_rms_px, settings.batch_residual_limit_px());
  EXPECT_EQ(result.outliers.size(), filter_outliers);
  EXPECT_NE(result.retest_skipped.find("fits the tracks only to"), std::string::npos)
      << result.retest_skipped;
}

TEST(BatchRetest, ASolutionThatFitsRetestsAsBefore) {
  const Rover r = rover_filtered();
  SfmResult result = r.filtered;
  adjust_on_inliers(r.data.camera, r.data.observations, r.settings, r.online_cam_from_world,
                    nullptr, &result);
  EXPECT_LT(result.batch.final_rms_px, 0.3);
  EXPECT_TRUE(result.retest_skipped.empty()) << result.retest_skipped;
}

// The rover, seed 1, with one good track made to drift slowly off its point from a quarter of
// its life on (3.5 px along u by its end): each residual stays within the limit, as the point
// triangulated from it follows it halfway.
struct SlowDrift {
  sim::Dataset data;
  int drifting = -1;  // that track
  std::set<int> true_outliers;  // the simulator's
  std::set<int> outliers() const {
    std::set<int> all = true_outliers;
    all.insert(drifting);
    return all;
  }
};

SlowDrift rover_with_a_slow_drift() {
  sim::SimulationOptions options;
  options.scenario = "rover";
  options.seed = 1;
  SlowDrift d{sim::simulate(options), -1, {}};
  for (const auto& o : d.data.outliers) d.true_outliers.insert(o.track);
  std::map<int, std::pair<int, int>> span;  // track -> first and last frame
  for (const auto& o : d.data.observations) {
    auto [it, added] = span.emplace(o.track, std::make_pair(o.frame, o.frame));
    it->second.first = std::min(it->second.first, o.frame);
    it->second.second = std::max(it->second.second, o.frame);
  }
  for (const auto& [track, frames] : span)
    if (!d.true_outliers.count(track) && frames.second - frames.first >= 60) d.drifting = track;
  if (d.drifting < 0) return d;
  const auto [first, last] = span[d.drifting];
  const int start = first + (last - first) / 4;
  for (auto& o : d.data.observations)
    if (o.track == d.drifting && o.frame > start)
      o.pixel.x() += 3.5 * (o.frame - start) / (last - start);
  return d;
}

std::set<int> rejected_tracks(const SlowDrift& d, const SfmSettings& settings) {
  std::set<int> rejected;
  for (const auto& o : run_sfm(d.data.camera, d.data.observations, settings).outliers)
    rejected.insert(o.track);
  return rejected;
}

// Over its length the batch rejects the slow drift; with the whole-track test off it keeps it.
TEST(BatchRetest, ASlowDriftIsRejectedOverTheTracksLength) {
  const SlowDrift d = rover_with_a_slow_drift();
  ASSERT_GE(d.drifting, 0);
  SfmSettings settings;
  EXPECT_EQ(rejected_tracks(d, settings), d.outliers());
  settings.batch_track_false_alarm = 1;  // every track would fail
  EXPECT_THROW(rejected_tracks(d, settings), std::invalid_argument);
  settings.batch_track_false_alarm = 0;
  EXPECT_EQ(rejected_tracks(d, settings), d.true_outliers);
}

// A filter whose test is far too tight (the paper's rule at 0.6 px) rejects the drift with dozens
// of good tracks; the batch takes the good ones back, and not the drift, whose every residual
// it explains but not their sum.
TEST(BatchRetest, ASlowDriftTheFilterRejectedIsNotTakenBack) {
  const SlowDrift d = rover_with_a_slow_drift();
  ASSERT_GE(d.drifting, 0);
  SfmSettings settings;
  settings.filter.outlier_test = OutlierTest::kPixels;
  settings.filter.outlier_threshold_px = 0.6;
  settings.batch_outlier_threshold_px = 1.6;  // the chi-square test's limit at 0.3 px
  EXPECT_GT(run_sfm(d.data.camera, d.data.observations, settings).taken_back, 20);
  EXPECT_EQ(rejected_tracks(d, settings), d.outliers());
  settings.batch_track_false_alarm = 0;
  EXPECT_EQ(rejected_tracks(d, settings), d.true_outliers);
}

}  // namespace
}  // namespace omnisfm::sfm
