#include "omnisfm/core/percentile.h"

#include <gtest/gtest.h>

namespace omnisfm::core {
namespace {

TEST(Percentile, TakesTheSortedEntryAtTheFractionOfTheCount) {
  const std::vector<double> odd = {5, 1, 4, 2, 3};
  EXPECT_EQ(percentile(odd, 0.5), 3);
  EXPECT_EQ(percentile(odd, 0), 1);
  EXPECT_EQ(percentile(odd, 0.95), 5);  // entry 4 of 0-4
  EXPECT_EQ(percentile(odd, 1), 5);
  // Of an even count the median is the upper middle entry.
  EXPECT_EQ(percentile({4, 1, 3, 2}, 0.5), 3);
  EXPECT_EQ(percentile({}, 0.5), 0);
}

TEST(Percentile, InPlaceGivesTheSameAndKeepsTheValues) {
  std::vector<double> values = {9, -2, 7, 7, 0.5, 3, 11, -8};
  const double copied = percentile(values, 0.5);
  std::vector<double> sorted = values;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(percentile_in_place(&values, 0.5), copied);
  EXPECT_EQ(copied, 7);
  std::sort(values.begin(), values.end());
  EXPECT_EQ(values, sorted);  // reordered, nothing lost
  std::vector<double> none;
  EXPECT_EQ(percentile_in_place(&none, 0.5), 0);
}

TEST(Percentile, OfARangeLeavesTheRestAlone) {
  std::vector<double> values = {6, 2, 9, 4, 100, -100};
  EXPECT_EQ(percentile_in_place(values.data(), values.data() + 4, 0.5), 6);  // {2, 4, 6, 9}
  EXPECT_EQ(values[4], 100);
  EXPECT_EQ(values[5], -100);
  EXPECT_EQ(percentile_in_place(values.data(), values.data(), 0.5), 0);
}

}  // namespace
}  // namespace omnisfm::core
