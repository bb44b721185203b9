#pragma once
// A checkerboard of any size in a view, found cheaply: OpenCV's sector-based detector asked for
// the smallest grid (3 x 3) with CALIB_CB_LARGER, without its exhaustive search, grows it into the
// whole board it sees. In about a third of the time of the exhaustive search for a given grid it
// tells where a board is worth that search, and what size of board the images show.

#include <opencv2/core.hpp>

namespace omnisfm::calib {

// The board an 8-bit grey view shows: its inner corners across and down as the detector meets
// them (either way round), or an empty size where none.
cv::Size board_seen(const cv::Mat& view);

// Whether a board of `board` points holds a grid of `grid`, either way round (board_detection.h
// takes a block of it turned a quarter too).
bool holds(cv::Size board, cv::Size grid);

}  // namespace omnisfm::calib
