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

// A good track that slowly drifts off its point (3.5 px by its end, along u) stays within the
// residual limit at every frame, as its point follows it halfway; over its length the batch
// rejects it, and with the whole-track test off it keeps it.
TEST(BatchRetest, ASlowDriftIsRejectedOverTheTracksLength) {
  sim::SimulationOptions options;
  options.scenario = "rover";
  options.seed = 1;
  sim::Dataset data = sim::simulate(options);
  std::set<int> true_outliers;
  for (const auto& o : data.outliers) true_outliers.insert(o.track);
  std::map<int, std::pair<int, int>> span;  // track -> first and last frame
  for (const auto& o : data.observations) {
    auto [it, added] = span.emplace(o.track, std::make_pair(o.frame, o.frame));
    it->second.first = std::min(it->second.first, o.frame);
    it->second.second = std::max(it->second.second, o.frame);
  }
  int drifting = -1;
  for (const auto& [track, frames] : span)
    if (!true_outliers.count(track) && frames.second - frames.first >= 60) drifting = track;
  ASSERT_GE(drifting, 0);
  const auto [first, last] = span[drifting];
  const int start = first + (last - first) / 4;
  for (auto& o : data.observations)
    if (o.track == drifting && o.frame > start)
      o.pixel.x() += 3.5 * (o.frame - start) / (last - start);

  SfmSettings settings;
  const SfmResult result = run_sfm(data.camera, data.observations, settings);
  std::set<int> rejected;
  for (const auto& o : result.outliers) rejected.insert(o.track);
  std::set<int> expected = true_outliers;
  expected.insert(drifting);
  EXPECT_EQ(rejected, expected);

  settings.batch_track_false_alarm = 0;
  const SfmResult without = run_sfm(data.camera, data.observations, settings);
  std::set<int> rejected_without;
  for (const auto& o : without.outliers) rejected_without.insert(o.track);
  EXPECT_EQ(rejected_without, true_outliers);
}

}  // namespace
}  // namespace omnisfm::sfm
