#include "../src/step_neighbourhoods.h"

#include <gtest/gtest.h>

#include <random>

#include "omnisfm/core/percentile.h"

namespace omnisfm::track {
namespace {

// Every track read one by one, as the tracker did before the grid: what the grid must give.
bool every_track_median(const std::vector<Eigen::Vector2d>& starts,
                        const std::vector<Eigen::Vector2d>& steps, double radius,
                        const Eigen::Vector2d& at, size_t skip, size_t min_tracks,
                        Eigen::Vector2d* step) {
  std::vector<double> xs, ys;
  for (size_t i = 0; i < starts.size(); ++i)
    if (i != skip && !((starts[i] - at).squaredNorm() > radius * radius)) {
      xs.push_back(steps[i].x());
      ys.push_back(steps[i].y());
    }
  if (xs.size() < min_tracks) return false;
  *step = Eigen::Vector2d(core::percentile(xs, 0.5), core::percentile(ys, 0.5));
  return true;
}

TEST(StepNeighbourhoods, GivesWhatReadingEveryTrackGives) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> across(0, 700), step(-6, 6), beyond(-300, 1000);
  constexpr double kRadius = 100;
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Vector2d> starts, steps;
    const int tracks = 1 + trial * 7;
    for (int i = 0; i < tracks; ++i) {
      starts.emplace_back(across(rng), across(rng));
      steps.emplace_back(step(rng), step(rng));
    }
    const StepNeighbourhoods neighbourhoods(starts, steps, kRadius);
    int found = 0;
    // At each start with itself left out (the jump check), and anywhere, inside the starts'
    // extent and far outside it (a lost track's last place).
    for (int q = 0; q < 200; ++q) {
      const bool at_start = q < tracks;
      const Eigen::Vector2d at = at_start ? starts[q] : Eigen::Vector2d(beyond(rng), beyond(rng));
      const size_t skip = at_start ? static_cast<size_t>(q) : starts.size();
      Eigen::Vector2d expected(-1, -1), got(-2, -2);
      const bool expected_found =
          every_track_median(starts, steps, kRadius, at, skip, 3, &expected);
      ASSERT_EQ(neighbourhoods.median_step(at, skip, 3, &got), expected_found)
          << "trial " << trial << " query " << q;
      if (!expected_found) continue;
      ++found;
      EXPECT_EQ(got, expected) << "trial " << trial << " query " << q;
    }
    if (tracks > 50) {
      EXPECT_GT(found, 50) << "trial " << trial;
    }
  }
}

TEST(StepNeighbourhoods, AStepAtTheRadiusCountsAndNoneBeyondIt) {
  const std::vector<Eigen::Vector2d> starts = {{0, 0}, {10, 0}, {0, 10}, {10.001, 0}};
  const std::vector<Eigen::Vector2d> steps = {{1, 1}, {2, 2}, {3, 3}, {50, 50}};
  const StepNeighbourhoods neighbourhoods(starts, steps, 10);
  Eigen::Vector2d step;
  ASSERT_TRUE(neighbourhoods.median_step({0, 0}, starts.size(), 3, &step));
  EXPECT_EQ(step, Eigen::Vector2d(2, 2));
  EXPECT_FALSE(neighbourhoods.median_step({0, 0}, 0, 3, &step));
  EXPECT_FALSE(neighbourhoods.median_step({1e9, -1e9}, starts.size(), 1, &step));
}

// A start within the radius by its rounded distance, whose cell, rounded, is two from the place's.
TEST(StepNeighbourhoods, AStartAtTheRadiusAcrossACellBoundaryCounts) {
  const double radius = 54.827348046468558;
  const std::vector<Eigen::Vector2d> starts = {
      {409.50489679916279, 0}, {1670.5339018679394, 0}, {3000, 0}};
  const Eigen::Vector2d at(1615.7065538214711, 0);
  ASSERT_LE((starts[1] - at).squaredNorm(), radius * radius);
  const StepNeighbourhoods neighbourhoods(starts, {{1, 0}, {2, 0}, {3, 0}}, radius);
  Eigen::Vector2d step;
  ASSERT_TRUE(neighbourhoods.median_step(at, starts.size(), 1, &step));
  EXPECT_EQ(step, Eigen::Vector2d(2, 0));
}

// Tracks a billion pixels apart, one not finite: the grid stays small and finds the same.
TEST(StepNeighbourhoods, FarApartOrNotFiniteStarts) {
  const std::vector<Eigen::Vector2d> starts = {
      {0, 0}, {5, 5}, {-5, 5}, {1e9, -1e9}, {1e9 + 5, -1e9}, {1e9, -1e9 + 5}, {NAN, 0}, {1e300, 0}};
  const std::vector<Eigen::Vector2d> steps = {{1, 1}, {2, 2}, {3, 3}, {4, 4},
                                              {5, 5}, {6, 6}, {7, 7}, {8, 8}};
  const StepNeighbourhoods neighbourhoods(starts, steps, 10);
  Eigen::Vector2d step;
  ASSERT_TRUE(neighbourhoods.median_step({0, 0}, starts.size(), 3, &step));
  EXPECT_EQ(step, Eigen::Vector2d(2, 2));
  ASSERT_TRUE(neighbourhoods.median_step({1e9, -1e9}, starts.size(), 3, &step));
  EXPECT_EQ(step, Eigen::Vector2d(5, 5));
  EXPECT_FALSE(neighbourhoods.median_step({NAN, 0}, starts.size(), 1, &step));
  ASSERT_TRUE(neighbourhoods.median_step({1e300, 0}, starts.size(), 1, &step));
  EXPECT_EQ(step, Eigen::Vector2d(8, 8));
  const StepNeighbourhoods beyond_range({{-1e308, 0}, {1e308, 0}, {1e308, 1}},
                                        {{1, 0}, {2, 0}, {3, 0}}, 10);
  ASSERT_TRUE(beyond_range.median_step({1e308, 0}, 3, 2, &step));
  EXPECT_EQ(step, Eigen::Vector2d(3, 0));
}

// The jump check's question, answered by counting where it can: the same answers as the medians
// give, with tracks that move together, that do not, and steps on the boundary itself.
TEST(StepNeighbourhoods, DepartsAsTheMediansSay) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> across(0, 300), unit(0, 1);
  constexpr double kRadius = 100, kMaxDeviation = 8;
  int departing = 0, staying = 0, counted_out = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<Eigen::Vector2d> starts, steps;
    const int tracks = 2 + trial;
    // Steps spread by 0.5 to 20 px about a common one, some whole pixels (ties and steps at the
    // boundary).
    const double spread = 0.5 + 0.5 * trial;
    std::normal_distribution<double> scatter(0, spread);
    for (int i = 0; i < tracks; ++i) {
      starts.emplace_back(across(rng), across(rng));
      Eigen::Vector2d s(3 + scatter(rng), -2 + scatter(rng));
      if (unit(rng) < 0.3) s = s.array().round();
      steps.push_back(s);
    }
    const StepNeighbourhoods neighbourhoods(starts, steps, kRadius);
    for (int i = 0; i < tracks; ++i) {
      Eigen::Vector2d median;
      // The track's own step, and steps exactly max_deviation from the median.
      std::vector<Eigen::Vector2d> asked = {steps[i]};
      if (neighbourhoods.median_step(starts[i], i, 3, &median)) {
        asked.push_back(median + Eigen::Vector2d(kMaxDeviation, 0));
        asked.push_back(median + Eigen::Vector2d(0, -kMaxDeviation));
      }
      for (const Eigen::Vector2d& step : asked) {
        const bool found = neighbourhoods.median_step(starts[i], i, 3, &median);
        const bool expected = found && (step - median).norm() > kMaxDeviation;
        ASSERT_EQ(neighbourhoods.departs(starts[i], i, 3, step, kMaxDeviation), expected)
            << "trial " << trial << " track " << i;
        if (!found) ++counted_out;
        (expected ? departing : staying) += 1;
      }
    }
  }
  // Both answers, and too few neighbours, were asked about.
  EXPECT_GT(departing, 50);
  EXPECT_GT(staying, 500);
  EXPECT_GT(counted_out, 5);
}

TEST(StepNeighbourhoods, NoTracks) {
  const StepNeighbourhoods neighbourhoods({}, {}, 100);
  Eigen::Vector2d step;
  EXPECT_FALSE(neighbourhoods.median_step({0, 0}, 0, 1, &step));
  EXPECT_FALSE(neighbourhoods.departs({0, 0}, 0, 1, {100, 100}, 8));
  EXPECT_THROW(StepNeighbourhoods({{0, 0}}, {}, 100), std::invalid_argument);
  EXPECT_THROW(StepNeighbourhoods({}, {}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::track
