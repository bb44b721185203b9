#include "omnisfm/calib/checkerboard_grid.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace omnisfm::calib {

std::vector<std::vector<cv::Point2f>> grid_blocks(const std::vector<cv::Point2f>& found,
                                                  cv::Size found_size, cv::Size grid) {
  CV_Assert(static_cast<std::size_t>(found_size.area()) == found.size());
  std::vector<std::vector<cv::Point2f>> blocks;
  const int cols = found_size.width, rows = found_size.height;
  const int w = grid.width, h = grid.height;
  const auto at = [&](int row, int col) { return found[static_cast<std::size_t>(row * cols + col)]; };
  for (int r0 = 0; r0 + h <= rows; ++r0)
    for (int c0 = 0; c0 + w <= cols; ++c0) {
      std::vector<cv::Point2f>& block = blocks.emplace_back();
      for (int i = 0; i < h; ++i)
        for (int j = 0; j < w; ++j) block.push_back(at(r0 + i, c0 + j));
    }
  // Turned a quarter: the block's (row i, column j) is the board's (row j, column h - 1 - i).
  if (w != h)
    for (int r0 = 0; r0 + w <= rows; ++r0)
      for (int c0 = 0; c0 + h <= cols; ++c0) {
        std::vector<cv::Point2f>& block = blocks.emplace_back();
        for (int i = 0; i < h; ++i)
          for (int j = 0; j < w; ++j) block.push_back(at(r0 + j, c0 + h - 1 - i));
      }
  return blocks;
}

double closest_corner_spacing(const std::vector<cv::Point2f>& corners, int width_n) {
  double closest = INFINITY;
  for (std::size_t k = 0; k < corners.size(); ++k) {
    if ((k + 1) % width_n != 0)
      closest = std::min<double>(closest, cv::norm(corners[k + 1] - corners[k]));
    if (k + width_n < corners.size())
      closest = std::min<double>(closest, cv::norm(corners[k + width_n] - corners[k]));
  }
  return closest;
}

bool squares_alternate(const cv::Mat& grey, const std::vector<cv::Point2f>& corners, int width_n,
                       double min_share) {
  CV_Assert(grey.type() == CV_8UC1 && width_n >= 2 && corners.size() % width_n == 0);
  const int height_n = static_cast<int>(corners.size()) / width_n;
  if (height_n < 2) return false;
  const auto at = [&](int r, int c) { return corners[static_cast<std::size_t>(r * width_n + c)]; };
  cv::Mat centres(height_n - 1, width_n - 1, CV_64F);
  for (int r = 0; r + 1 < height_n; ++r)
    for (int c = 0; c + 1 < width_n; ++c) {
      const cv::Point2f centre =
          0.25f * (at(r, c) + at(r, c + 1) + at(r + 1, c) + at(r + 1, c + 1));
      cv::Mat patch;
      cv::getRectSubPix(grey, cv::Size(3, 3), centre, patch, CV_32F);
      centres.at<double>(r, c) = cv::mean(patch)[0];
    }
  // Counted with the first square taken as the darker, then as the lighter; a pair alike (a glare
  // over both) counts for neither.
  int pairs = 0, first_darker = 0, first_lighter = 0;
  const auto count = [&](double step, double parity) {
    ++pairs;
    first_darker += parity * step > 0;
    first_lighter += parity * step < 0;
  };
  for (int r = 0; r < centres.rows; ++r)
    for (int c = 0; c < centres.cols; ++c) {
      const double parity = (r + c) % 2 == 0 ? 1 : -1;
      if (c + 1 < centres.cols) count(centres.at<double>(r, c + 1) - centres.at<double>(r, c), parity);
      if (r + 1 < centres.rows) count(centres.at<double>(r + 1, c) - centres.at<double>(r, c), parity);
    }
  return pairs > 0 && std::max(first_darker, first_lighter) >= min_share * pairs;
}

}  // namespace omnisfm::calib
