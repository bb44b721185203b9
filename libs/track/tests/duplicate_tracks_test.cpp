#include "../src/duplicate_tracks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace omnisfm::track {
namespace {

// Every pair read, in the order of the indices.
std::vector<bool> reading_every_pair(const std::vector<Eigen::Vector2d>& positions,
                                     const std::vector<std::pair<int, int>>& started,
                                     double separation) {
  std::vector<bool> ended(positions.size(), false);
  for (size_t i = 0; i < positions.size(); ++i)
    for (size_t j = i + 1; j < positions.size(); ++j) {
      if (ended[i] || ended[j] || !((positions[i] - positions[j]).norm() < separation)) continue;
      ended[started[i] > started[j] ? i : j] = true;
    }
  return ended;
}

// Crowded tracks (chains of three and more within the separation), some with the same first
// frame, a few not finite: the same ends as reading every pair.
TEST(YoungerDuplicates, EndAsReadingEveryPair) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> place(0, 40);
  std::uniform_int_distribution<int> frame(0, 5);
  int ends = 0;
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Eigen::Vector2d> positions;
    std::vector<std::pair<int, int>> started;
    for (int id = 0; id < 120; ++id) {
      positions.emplace_back(place(random), place(random));
      started.emplace_back(frame(random), id);
    }
    positions[7].x() = NAN;
    positions[11].y() = INFINITY;
    const std::vector<bool> ended = younger_duplicates(positions, started, 3);
    ASSERT_EQ(ended, reading_every_pair(positions, started, 3)) << "trial " << trial;
    ends += static_cast<int>(std::count(ended.begin(), ended.end(), true));
    EXPECT_FALSE(ended[7]);
    EXPECT_FALSE(ended[11]);
  }
  EXPECT_GT(ends, 50 * 20);  // crowded enough to test something
}

TEST(YoungerDuplicates, TheYoungerOfTwoEnds) {
  const std::vector<Eigen::Vector2d> positions = {{10, 10}, {11, 10.5}, {30, 30}};
  EXPECT_EQ(younger_duplicates(positions, {{4, 0}, {2, 1}, {0, 2}}, 3),
            (std::vector<bool>{true, false, false}));
  // Started in the same frame: the greater id.
  EXPECT_EQ(younger_duplicates(positions, {{2, 5}, {2, 1}, {0, 2}}, 3),
            (std::vector<bool>{true, false, false}));
  EXPECT_EQ(younger_duplicates(positions, {{2, 5}, {2, 1}, {0, 2}}, 1),
            (std::vector<bool>{false, false, false}));
  EXPECT_THROW(younger_duplicates(positions, {{0, 0}}, 3), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::track
