#pragma once
// A checkerboard's grid of inner corners as a detector returns it: row by row, width_n a row
// (mrcal's board order). What board_detection.h needs of one: its W x H blocks when the board
// found is larger than the grid asked for, how squeezed a block is, and whether its squares
// alternate dark and light as a checkerboard's must.

#include <opencv2/core.hpp>
#include <vector>

namespace omnisfm::calib {

// The W x H blocks of a board found larger: `found` row by row over found_size (columns, rows),
// each block in the grid's order. A block of a regular board is a board of its own. A board
// lying across (found_size.width >= H, found_size.height >= W) also gives its blocks turned a
// quarter: a rotation of the board, never its mirror image.
std::vector<std::vector<cv::Point2f>> grid_blocks(const std::vector<cv::Point2f>& found,
                                                  cv::Size found_size, cv::Size grid);

// Orders a board found in an image (x right, y down; `found` row by row over found_size) so that
// its first step down is a quarter turn clockwise from its first step across, as OpenCV orders a
// board of exactly the pattern's size: one it finds larger comes mirrored, each row reversed.
// (For a planar board a mirrored order is the board turned over, which fits as well; the same
// order for every board keeps their poses alike.)
void order_clockwise(std::vector<cv::Point2f>* found, cv::Size found_size);

// The smallest distance between neighbouring corners (across or down) of a grid width_n wide.
double closest_corner_spacing(const std::vector<cv::Point2f>& corners, int width_n);

// How much the squares in and around a grid look like a checkerboard's in `grey` (8 bits). Each
// square is sampled at four points 40 % of the way from its centre to its corners; two squares
// are apart when the darkest sample of one is lighter than the other's lightest.
struct SquareChecks {
  // Of the pairs of the grid's own neighbouring squares (across and down), the share apart as a
  // checkerboard colours them, under the better of its two colourings. 1 for a board seen
  // plainly; a glare or a shadow spoils the pairs of a square or two. A grid that skips a row of
  // the board (its corners real saddles, two squares apart in one place and one in another)
  // scores low: a "square" two squares tall holds both greys.
  double alternating = 0;
  // Of the squares just beyond each edge (their outer corners a step on), the share of pairs
  // apart along that edge, each with its neighbour beyond and with the grid's square within, at
  // the weakest edge. A grid whose edge runs along the board's border (corners where the squares
  // meet the white margin, not saddles) scores low there.
  double weakest_edge = 0;
};
// Both 0 for a grid under 2 x 2.
SquareChecks check_squares(const cv::Mat& grey, const std::vector<cv::Point2f>& corners,
                           int width_n);

}  // namespace omnisfm::calib
