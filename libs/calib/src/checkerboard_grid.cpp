#include "omnisfm/calib/checkerboard_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>
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

void order_clockwise(std::vector<cv::Point2f>* found, cv::Size found_size) {
  CV_Assert(static_cast<std::size_t>(found_size.area()) == found->size());
  const int cols = found_size.width;
  if (cols < 2 || found_size.height < 2) return;
  const std::vector<cv::Point2f>& c = *found;
  const cv::Point2f across = c[1] - c[0], down = c[static_cast<std::size_t>(cols)] - c[0];
  if (across.x * down.y - across.y * down.x >= 0) return;
  for (int r = 0; r < found_size.height; ++r)
    std::reverse(found->begin() + r * cols, found->begin() + (r + 1) * cols);
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

namespace {

// A quadrilateral's darkest and lightest grey at four points 40 % of the way from its centre to
// its corners.
std::pair<double, double> grey_range(const cv::Mat& grey, const cv::Point2f (&corner)[4]) {
  const cv::Point2f centre = 0.25f * (corner[0] + corner[1] + corner[2] + corner[3]);
  double low = INFINITY, high = -INFINITY;
  for (const cv::Point2f& k : corner) {
    cv::Mat patch;
    cv::getRectSubPix(grey, cv::Size(1, 1), 0.6f * centre + 0.4f * k, patch, CV_32F);
    low = std::min<double>(low, patch.at<float>(0, 0));
    high = std::max<double>(high, patch.at<float>(0, 0));
  }
  return {low, high};
}

bool apart(const std::pair<double, double>& a, const std::pair<double, double>& b) {
  return a.second < b.first || b.second < a.first;
}

}  // namespace

double weakest_edge_share(const cv::Mat& grey, const std::vector<cv::Point2f>& corners,
                          int width_n) {
  CV_Assert(grey.type() == CV_8UC1 && width_n >= 2 && corners.size() % width_n == 0);
  const int height_n = static_cast<int>(corners.size()) / width_n;
  if (height_n < 2) return 0;
  const auto at = [&](int r, int c) { return corners[static_cast<std::size_t>(r * width_n + c)]; };
  // Each edge as its corners in order and, per corner, the next corner inwards.
  struct Edge {
    std::vector<cv::Point2f> on, in;
  };
  std::vector<Edge> edges(4);
  for (int c = 0; c < width_n; ++c) {
    edges[0].on.push_back(at(0, c));
    edges[0].in.push_back(at(1, c));
    edges[1].on.push_back(at(height_n - 1, c));
    edges[1].in.push_back(at(height_n - 2, c));
  }
  for (int r = 0; r < height_n; ++r) {
    edges[2].on.push_back(at(r, 0));
    edges[2].in.push_back(at(r, 1));
    edges[3].on.push_back(at(r, width_n - 1));
    edges[3].in.push_back(at(r, width_n - 2));
  }
  double weakest = 1;
  for (const Edge& e : edges) {
    std::vector<std::pair<double, double>> outside, inside;
    for (std::size_t k = 0; k + 1 < e.on.size(); ++k) {
      const cv::Point2f out_k = 2 * e.on[k] - e.in[k], out_next = 2 * e.on[k + 1] - e.in[k + 1];
      const cv::Point2f beyond[4] = {e.on[k], e.on[k + 1], out_k, out_next};
      const cv::Point2f within[4] = {e.on[k], e.on[k + 1], e.in[k], e.in[k + 1]};
      outside.push_back(grey_range(grey, beyond));
      inside.push_back(grey_range(grey, within));
    }
    int pairs = 0, passed = 0;
    for (std::size_t k = 0; k < outside.size(); ++k) {
      ++pairs;
      passed += apart(outside[k], inside[k]);
      if (k + 1 < outside.size()) {
        ++pairs;
        passed += apart(outside[k], outside[k + 1]);
      }
    }
    weakest = std::min(weakest, static_cast<double>(passed) / pairs);
  }
  return weakest;
}

double alternating_share(const cv::Mat& grey, const std::vector<cv::Point2f>& corners,
                         int width_n) {
  CV_Assert(grey.type() == CV_8UC1 && width_n >= 2 && corners.size() % width_n == 0);
  const int height_n = static_cast<int>(corners.size()) / width_n;
  if (height_n < 2) return 0;
  const auto at = [&](int r, int c) { return corners[static_cast<std::size_t>(r * width_n + c)]; };
  // Per square, its darkest and its lightest sample.
  cv::Mat darkest(height_n - 1, width_n - 1, CV_64F), lightest(height_n - 1, width_n - 1, CV_64F);
  for (int r = 0; r + 1 < height_n; ++r)
    for (int c = 0; c + 1 < width_n; ++c) {
      const cv::Point2f corner[4] = {at(r, c), at(r, c + 1), at(r + 1, c), at(r + 1, c + 1)};
      const auto [low, high] = grey_range(grey, corner);
      darkest.at<double>(r, c) = low;
      lightest.at<double>(r, c) = high;
    }
  // Counted with the first square taken as dark, then as light.
  int pairs = 0, first_dark = 0, first_light = 0;
  const auto count = [&](int r, int c, int r2, int c2) {
    ++pairs;
    const bool dark_here = (r + c) % 2 == 0;  // under the first count
    const auto apart = [&](int dr, int dc, int lr, int lc) {
      return lightest.at<double>(dr, dc) < darkest.at<double>(lr, lc);
    };
    first_dark += dark_here ? apart(r, c, r2, c2) : apart(r2, c2, r, c);
    first_light += dark_here ? apart(r2, c2, r, c) : apart(r, c, r2, c2);
  };
  for (int r = 0; r + 1 < height_n; ++r)
    for (int c = 0; c + 1 < width_n; ++c) {
      if (c + 2 < width_n) count(r, c, r, c + 1);
      if (r + 2 < height_n) count(r, c, r + 1, c);
    }
  return pairs > 0 ? static_cast<double>(std::max(first_dark, first_light)) / pairs : 0;
}

}  // namespace omnisfm::calib
