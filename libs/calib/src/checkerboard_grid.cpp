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

using GreyRange = std::pair<double, double>;  // darkest, lightest

// A quadrilateral's darkest and lightest grey at four points 40 % of the way from its centre to
// its corners.
GreyRange grey_range(const cv::Mat& grey, const cv::Point2f (&corner)[4]) {
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

// Whether `dark`'s lightest sample is darker than `light`'s darkest.
bool darker(const GreyRange& dark, const GreyRange& light) { return dark.second < light.first; }

bool apart(const GreyRange& a, const GreyRange& b) { return darker(a, b) || darker(b, a); }

}  // namespace

SquareChecks check_squares(const cv::Mat& grey, const std::vector<cv::Point2f>& corners,
                           int width_n) {
  CV_Assert(grey.type() == CV_8UC1 && width_n >= 2 && corners.size() % width_n == 0);
  const int rows = static_cast<int>(corners.size()) / width_n, cols = width_n;
  SquareChecks checks;
  if (rows < 2) return checks;
  // The grid grown by a ring of corners a step beyond each edge, so that its squares are the
  // grid's own (1 .. rows - 1, 1 .. cols - 1) and around them the ones just beyond its edges.
  const int grown_cols = cols + 2;
  std::vector<cv::Point2f> grown(static_cast<std::size_t>((rows + 2) * grown_cols));
  const auto at = [&](int r, int c) -> cv::Point2f& {
    return grown[static_cast<std::size_t>(r * grown_cols + c)];
  };
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) at(r + 1, c + 1) = corners[static_cast<std::size_t>(r * cols + c)];
  for (int c = 1; c <= cols; ++c) {
    at(0, c) = 2 * at(1, c) - at(2, c);
    at(rows + 1, c) = 2 * at(rows, c) - at(rows - 1, c);
  }
  for (int r = 0; r <= rows + 1; ++r) {
    at(r, 0) = 2 * at(r, 1) - at(r, 2);
    at(r, cols + 1) = 2 * at(r, cols) - at(r, cols - 1);
  }
  std::vector<GreyRange> ranges(static_cast<std::size_t>((rows + 1) * (cols + 1)));
  const auto square = [&](int i, int j) -> GreyRange& {
    return ranges[static_cast<std::size_t>(i * (cols + 1) + j)];
  };
  for (int i = 0; i <= rows; ++i)
    for (int j = 0; j <= cols; ++j) {
      const cv::Point2f corner[4] = {at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)};
      square(i, j) = grey_range(grey, corner);
    }

  // The grid's own squares, counted with its first square taken as dark, then as light.
  int pairs = 0, first_dark = 0, first_light = 0;
  const auto count = [&](int i, int j, int i2, int j2) {
    ++pairs;
    const bool dark_here = (i + j) % 2 == 0;  // under the first count
    const GreyRange &here = square(i, j), &next = square(i2, j2);
    first_dark += dark_here ? darker(here, next) : darker(next, here);
    first_light += dark_here ? darker(next, here) : darker(here, next);
  };
  for (int i = 1; i < rows; ++i)
    for (int j = 1; j < cols; ++j) {
      if (j + 1 < cols) count(i, j, i, j + 1);
      if (i + 1 < rows) count(i, j, i + 1, j);
    }
  checks.alternating = pairs > 0 ? static_cast<double>(std::max(first_dark, first_light)) / pairs : 0;

  // Along each edge, the squares beyond it against each other and against the grid's own: from
  // the square beyond the edge's first stretch, a step along and a step inwards to the grid's.
  struct Edge {
    int i, j, di, dj, in_i, in_j, length;
  };
  const Edge edges[4] = {{0, 1, 0, 1, 1, 0, cols - 1},
                         {rows, 1, 0, 1, -1, 0, cols - 1},
                         {1, 0, 1, 0, 0, 1, rows - 1},
                         {1, cols, 1, 0, 0, -1, rows - 1}};
  checks.weakest_edge = 1;
  for (const Edge& e : edges) {
    int edge_pairs = 0, passed = 0;
    for (int k = 0; k < e.length; ++k) {
      const int i = e.i + k * e.di, j = e.j + k * e.dj;
      ++edge_pairs;
      passed += apart(square(i, j), square(i + e.in_i, j + e.in_j));
      if (k + 1 < e.length) {
        ++edge_pairs;
        passed += apart(square(i, j), square(i + e.di, j + e.dj));
      }
    }
    checks.weakest_edge = std::min(checks.weakest_edge, static_cast<double>(passed) / edge_pairs);
  }
  return checks;
}

}  // namespace omnisfm::calib
