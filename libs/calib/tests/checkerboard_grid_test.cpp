// A board's grid: its blocks, their spacing, and whether its squares alternate, on boards drawn
// flat in an image.

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "omnisfm/calib/checkerboard_grid.h"

namespace omnisfm::calib {
namespace {

// The cross product of a grid's first step across and first step down: its handedness.
double handedness(const std::vector<cv::Point2f>& corners, int width_n) {
  const cv::Point2f across = corners[1] - corners[0], down = corners[width_n] - corners[0];
  return across.x * down.y - across.y * down.x;
}

// A grid of cols x rows corners at (x0 + c * step, y0 + r * step), row by row.
std::vector<cv::Point2f> regular_grid(int cols, int rows, float step, float x0 = 40,
                                      float y0 = 30) {
  std::vector<cv::Point2f> corners;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) corners.emplace_back(x0 + c * step, y0 + r * step);
  return corners;
}

TEST(CheckerboardGrid, ABoardLargerThanTheGridGivesEveryBlockTurnedNeverMirrored) {
  const std::vector<cv::Point2f> found = regular_grid(9, 7, 10);
  const std::vector<std::vector<cv::Point2f>> blocks = grid_blocks(found, {9, 7}, {7, 5});
  // 3 x 3 blocks lying as the board does, 5 x 1 across it.
  ASSERT_EQ(blocks.size(), 14u);
  for (const std::vector<cv::Point2f>& block : blocks) {
    ASSERT_EQ(block.size(), 35u);
    // A rotation keeps the board's handedness; a mirror image would flip it.
    EXPECT_GT(handedness(block, 7), 0);
    // Neighbours in the block are neighbours on the board.
    EXPECT_DOUBLE_EQ(closest_corner_spacing(block, 7), 10);
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c + 1 < 7; ++c)
        EXPECT_DOUBLE_EQ(cv::norm(block[r * 7 + c + 1] - block[r * 7 + c]), 10);
  }
  // The first block is the board's top left, in its order.
  EXPECT_EQ(blocks[0][0], found[0]);
  EXPECT_EQ(blocks[0][7], found[9]);
  // A board found the grid's size gives itself.
  EXPECT_EQ(grid_blocks(regular_grid(7, 5, 10), {7, 5}, {7, 5}).size(), 1u);
  EXPECT_EQ(grid_blocks(regular_grid(7, 5, 10), {7, 5}, {7, 5})[0], regular_grid(7, 5, 10));
}

TEST(CheckerboardGrid, TheClosestSpacingIsTheSmallestStepAcrossOrDown) {
  std::vector<cv::Point2f> corners = regular_grid(4, 3, 12);
  corners[6].y += 5;  // row 1, column 2 moves down towards row 2
  EXPECT_NEAR(closest_corner_spacing(corners, 4), 7, 1e-5);
  EXPECT_NEAR(closest_corner_spacing(regular_grid(4, 3, 12), 4), 12, 1e-5);
}

// A checkerboard of squares `step` pixels wide, its inner corners at regular_grid(cols, rows).
cv::Mat drawn_board(int cols, int rows, int step) {
  cv::Mat image(rows * step + 100, cols * step + 120, CV_8UC1, cv::Scalar(200));
  for (int r = -1; r < rows; ++r)
    for (int c = -1; c < cols; ++c)
      if ((r + c) % 2 != 0) {
        const cv::Point corner(40 + c * step, 30 + r * step);
        cv::rectangle(image, cv::Rect(corner.x, corner.y, step, step), cv::Scalar(40), cv::FILLED);
      }
  return image;
}

TEST(CheckerboardGrid, ARealGridsSquaresAlternateAndOneThatSkipsARowsDoNot) {
  const cv::Mat image = drawn_board(9, 8, 16);
  const std::vector<cv::Point2f> all = regular_grid(9, 8, 16);
  EXPECT_TRUE(squares_alternate(image, all, 9));
  // The same corners, rows 0, 1, 3, 5 and 6: real saddles, but two squares apart here and one
  // there, as the sector-based detector returned them from a bent Kaidan board.
  std::vector<cv::Point2f> skipping;
  for (int r : {0, 1, 3, 5, 6})
    for (int c = 0; c < 9; ++c) skipping.push_back(all[r * 9 + c]);
  EXPECT_FALSE(squares_alternate(image, skipping, 9));
  // A column skipped as well as a row.
  std::vector<cv::Point2f> both;
  for (int r : {0, 1, 2, 4})
    for (int c : {0, 1, 3, 4, 5}) both.push_back(all[r * 9 + c]);
  EXPECT_FALSE(squares_alternate(image, both, 5));
  // Which colour comes first does not matter: the grid from its second column on.
  std::vector<cv::Point2f> shifted;
  for (int r = 0; r < 8; ++r)
    for (int c = 1; c < 9; ++c) shifted.push_back(all[r * 9 + c]);
  EXPECT_TRUE(squares_alternate(image, shifted, 8));
  // A glare over one square of 56 is allowed; over a quarter of them, not.
  cv::Mat glare = image.clone();
  cv::rectangle(glare, cv::Rect(40 + 3 * 16 + 2, 30 + 2 * 16 + 2, 12, 12), cv::Scalar(250),
                cv::FILLED);
  EXPECT_TRUE(squares_alternate(glare, all, 9));
  cv::rectangle(glare, cv::Rect(40, 30, 4 * 16, 4 * 16), cv::Scalar(250), cv::FILLED);
  EXPECT_FALSE(squares_alternate(glare, all, 9));
}

}  // namespace
}  // namespace omnisfm::calib
