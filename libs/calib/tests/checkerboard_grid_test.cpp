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
    // Neighbours in the block, across and down, are neighbours on the board.
    EXPECT_DOUBLE_EQ(closest_corner_spacing(block, 7), 10);
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c < 7; ++c) {
        if (c + 1 < 7) {
          EXPECT_DOUBLE_EQ(cv::norm(block[r * 7 + c + 1] - block[r * 7 + c]), 10);
        }
        if (r + 1 < 5) {
          EXPECT_DOUBLE_EQ(cv::norm(block[(r + 1) * 7 + c] - block[r * 7 + c]), 10);
        }
      }
  }
  // The first block is the board's top left, in its order.
  EXPECT_EQ(blocks[0][0], found[0]);
  EXPECT_EQ(blocks[0][7], found[9]);
  // The first block turned a quarter: down the board across it, leftwards down it.
  EXPECT_EQ(blocks[9][0], found[4]);
  EXPECT_EQ(blocks[9][1], found[13]);
  EXPECT_EQ(blocks[9][7], found[3]);
  // A board found smaller than the grid has no block.
  EXPECT_TRUE(grid_blocks(regular_grid(6, 5, 10), {6, 5}, {7, 5}).empty());
  // A board found the grid's size gives itself.
  EXPECT_EQ(grid_blocks(regular_grid(7, 5, 10), {7, 5}, {7, 5}).size(), 1u);
  EXPECT_EQ(grid_blocks(regular_grid(7, 5, 10), {7, 5}, {7, 5})[0], regular_grid(7, 5, 10));
}

TEST(CheckerboardGrid, ABoardFoundMirroredIsOrderedClockwise) {
  // Rows reversed: across leftwards, down downwards, as OpenCV returns a board found larger.
  std::vector<cv::Point2f> found;
  for (int r = 0; r < 7; ++r)
    for (int c = 8; c >= 0; --c) found.emplace_back(40 + c * 10.0f, 30 + r * 10.0f);
  ASSERT_LT(handedness(found, 9), 0);
  order_clockwise(&found, {9, 7});
  EXPECT_GT(handedness(found, 9), 0);
  EXPECT_EQ(found, regular_grid(9, 7, 10));
  // One already clockwise stays as it is.
  order_clockwise(&found, {9, 7});
  EXPECT_EQ(found, regular_grid(9, 7, 10));
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

TEST(CheckerboardGrid, ARealGridsSquaresAlternateAndOneThatSkipsARowDoesNot) {
  const cv::Mat image = drawn_board(9, 8, 16);
  const std::vector<cv::Point2f> all = regular_grid(9, 8, 16);
  EXPECT_DOUBLE_EQ(check_squares(image, all, 9).alternating, 1);
  // Corners of chosen rows and columns of the board: real saddles, but two squares apart in
  // places, as the sector-based detector returned them from a bent Kaidan board (its grid scored
  // 0.42 there, every other board of the real sets 1).
  const auto picked = [&](std::vector<int> rows, std::vector<int> cols) {
    std::vector<cv::Point2f> corners;
    for (int r : rows)
      for (int c : cols) corners.push_back(all[r * 9 + c]);
    return corners;
  };
  const std::vector<int> seven = {0, 1, 2, 3, 4, 5, 6};
  // Measured: 0.263 for a row skipped inside, 0.711 for one at the block's edge, 0.235 for a row
  // and a column.
  EXPECT_NEAR(check_squares(image, picked({0, 1, 3, 5, 6}, seven), 7).alternating, 0.263, 0.01);
  EXPECT_NEAR(check_squares(image, picked({0, 2, 3, 4, 5}, seven), 7).alternating, 0.711, 0.01);
  EXPECT_NEAR(check_squares(image, picked({0, 1, 2, 4}, {0, 1, 3, 4, 5}), 5).alternating, 0.235,
              0.01);
  // Which colour comes first does not matter: the grid from its second column on.
  std::vector<cv::Point2f> shifted;
  for (int r = 0; r < 8; ++r)
    for (int c = 1; c < 9; ++c) shifted.push_back(all[r * 9 + c]);
  EXPECT_DOUBLE_EQ(check_squares(image, shifted, 8).alternating, 1);
  // A glare over one square of a 7 x 5 block is allowed (measured 0.895); over nine, not
  // (0.605).
  const std::vector<cv::Point2f> block = picked({1, 2, 3, 4, 5}, seven);
  cv::Mat glare = image.clone();
  cv::rectangle(glare, cv::Rect(40 + 3 * 16 + 2, 30 + 2 * 16 + 2, 12, 12), cv::Scalar(250),
                cv::FILLED);  // a dark square
  EXPECT_NEAR(check_squares(glare, block, 7).alternating, 0.895, 0.01);
  cv::rectangle(glare, cv::Rect(40 + 2 * 16 + 2, 30 + 2 * 16 + 2, 3 * 16, 3 * 16), cv::Scalar(250),
                cv::FILLED);
  EXPECT_NEAR(check_squares(glare, block, 7).alternating, 0.605, 0.01);
  // Under two rows there are no squares.
  EXPECT_EQ(check_squares(image, picked({0}, seven), 7).alternating, 0);
}

TEST(CheckerboardGrid, AGridWhoseEdgeRunsAlongTheBoardsBorderIsTold) {
  // A board of 9 x 8 inner corners and its outermost squares, on a white margin.
  const cv::Mat image = drawn_board(9, 8, 16);
  EXPECT_DOUBLE_EQ(check_squares(image, regular_grid(9, 8, 16), 9).weakest_edge, 1);
  // A block inside the board, and one at its corner.
  EXPECT_DOUBLE_EQ(
      check_squares(image, regular_grid(7, 5, 16, 40 + 16, 30 + 16), 7).weakest_edge, 1);
  EXPECT_DOUBLE_EQ(check_squares(image, regular_grid(7, 5, 16), 7).weakest_edge, 1);
  // The same grid one row up, its top row where the outermost squares meet the margin: its
  // squares are the board's and alternate, but beyond its top edge is the margin (measured 0.273;
  // a grid shifted so detected the parabolic rig's boards 10 px off).
  const std::vector<cv::Point2f> on_border = regular_grid(7, 5, 16, 40, 30 - 16);
  EXPECT_DOUBLE_EQ(check_squares(image, on_border, 7).alternating, 1);
  EXPECT_NEAR(check_squares(image, on_border, 7).weakest_edge, 0.273, 0.01);
  // One column left, likewise (0.286).
  EXPECT_NEAR(check_squares(image, regular_grid(7, 5, 16, 40 - 16, 30), 7).weakest_edge, 0.286,
              0.01);
}

}  // namespace
}  // namespace omnisfm::calib
