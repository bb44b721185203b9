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

// The smallest distance between neighbouring corners (across or down) of a grid width_n wide.
double closest_corner_spacing(const std::vector<cv::Point2f>& corners, int width_n);

// Whether the squares between the corners alternate dark and light in `grey` (8 bits): each
// square's centre against its neighbours' across and down, at least `min_share` of the pairs
// (a glare or a shadow may take a few). A grid that skips a row of the board (its corners real
// saddles, two squares apart in one place and one in another) fails it.
bool squares_alternate(const cv::Mat& grey, const std::vector<cv::Point2f>& corners, int width_n,
                       double min_share = 0.9);

}  // namespace omnisfm::calib
