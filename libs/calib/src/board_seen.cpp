#include "omnisfm/calib/board_seen.h"

#include <opencv2/calib3d.hpp>
#include <vector>

namespace omnisfm::calib {

cv::Size board_seen(const cv::Mat& view) {
  const cv::Size smallest(3, 3);  // OpenCV's detector takes no smaller grid
  std::vector<cv::Point2f> corners;
  cv::Mat meta;  // a cell per corner of the board found
  if (!cv::findChessboardCornersSB(view, smallest, corners, cv::CALIB_CB_LARGER, meta)) return {};
  return meta.empty() ? smallest : cv::Size(meta.cols, meta.rows);
}

bool holds(cv::Size board, cv::Size grid) {
  return (board.width >= grid.width && board.height >= grid.height) ||
         (board.width >= grid.height && board.height >= grid.width);
}

}  // namespace omnisfm::calib
