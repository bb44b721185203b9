#include "shi_tomasi.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace omnisfm::track {
namespace {

// Index of row or column i of n (n >= 2) with OpenCV's default border (reflected about the
// edge pixel), as the Sobel filter and the box filter in cv::cornerMinEigenVal use.
int reflect_101(int i, int n) { return i < 0 ? -i : i >= n ? 2 * n - 2 - i : i; }

// The smaller eigenvalue per pixel, as cv::cornerMinEigenVal(image, 3, 3) computes it (up to
// float rounding: its box filter sums in double).
cv::Mat min_eigenvalues(const cv::Mat& image) {
  const int rows = image.rows, cols = image.cols;
  // The scale cv::cornerMinEigenVal gives 8-bit images: 1 / (2^(3 - 1) * 3 * 255).
  const double scale = 1.0 / (4 * 3 * 255.0);
  cv::Mat dx, dy;
  cv::Sobel(image, dx, CV_32F, 1, 0, 3, scale, 0, cv::BORDER_DEFAULT);
  cv::Sobel(image, dy, CV_32F, 0, 1, 3, scale, 0, cv::BORDER_DEFAULT);
  cv::Mat eigenvalues(rows, cols, CV_32F);
  using Row = Eigen::Map<const Eigen::ArrayXf>;
  Eigen::ArrayXf xx(cols), xy(cols), yy(cols);  // the moments summed down three rows
  Eigen::ArrayXf a(cols), b(cols), c(cols);     // and across three columns
  for (int y = 0; y < rows; ++y) {
    const Row dx0(dx.ptr<float>(reflect_101(y - 1, rows)), cols), dx1(dx.ptr<float>(y), cols),
        dx2(dx.ptr<float>(reflect_101(y + 1, rows)), cols);
    const Row dy0(dy.ptr<float>(reflect_101(y - 1, rows)), cols), dy1(dy.ptr<float>(y), cols),
        dy2(dy.ptr<float>(reflect_101(y + 1, rows)), cols);
    xx = dx0.square() + dx1.square() + dx2.square();
    xy = dx0 * dy0 + dx1 * dy1 + dx2 * dy2;
    yy = dy0.square() + dy1.square() + dy2.square();
    for (auto [sum, across] : {std::pair{&xx, &a}, std::pair{&xy, &b}, std::pair{&yy, &c}}) {
      const Eigen::ArrayXf& s = *sum;
      Eigen::ArrayXf& t = *across;
      t.segment(1, cols - 2) = s.head(cols - 2) + s.segment(1, cols - 2) + s.tail(cols - 2);
      t(0) = s(0) + 2 * s(1);
      t(cols - 1) = s(cols - 1) + 2 * s(cols - 2);
    }
    // As cv::cornerMinEigenVal: with a = xx / 2, c = yy / 2, the smaller eigenvalue of
    // [xx xy; xy yy] is a + c - sqrt((a - c)^2 + xy^2).
    a *= 0.5f;
    c *= 0.5f;
    Eigen::Map<Eigen::ArrayXf>(eigenvalues.ptr<float>(y), cols) =
        (a + c) - ((a - c).square() + b.square()).sqrt();
  }
  return eigenvalues;
}

struct Candidate {
  float value;
  int offset;  // y * cols + x
};

}  // namespace

std::vector<cv::Point2f> shi_tomasi_corners(const cv::Mat& image, int max_corners,
                                            double quality_level, double min_distance,
                                            const cv::Mat& mask) {
  CV_Assert(image.type() == CV_8UC1 && mask.type() == CV_8UC1 && mask.size() == image.size());
  CV_Assert(max_corners > 0 && quality_level > 0 && min_distance >= 1);
  const int rows = image.rows, cols = image.cols;
  if (rows < 3 || cols < 3) return {};
  const cv::Mat eigenvalues = min_eigenvalues(image);
  double strongest = 0;
  cv::minMaxLoc(eigenvalues, nullptr, &strongest, nullptr, nullptr, mask);
  const float threshold = static_cast<float>(strongest * quality_level);

  // Local maxima (of the 3 x 3 neighbourhood) above the threshold, off the outermost pixels. The
  // neighbourhood maxima are array operations, and the candidates are written without a branch
  // per pixel (most pixels are not candidates, and a branch on that would mostly mispredict).
  std::vector<Candidate> candidates(static_cast<size_t>(cols));
  size_t count = 0;
  const Eigen::Index inner = cols - 2;
  using Row = Eigen::Map<const Eigen::ArrayXf>;
  // Of each row: the maximum over each pixel and its left and right neighbours.
  const auto across = [&](int y, Eigen::ArrayXf* out) {
    const Row e(eigenvalues.ptr<float>(y), cols);
    *out = e.head(inner).max(e.segment(1, inner)).max(e.tail(inner));
  };
  Eigen::ArrayXf above(inner), here(inner), below(inner), neighbourhood(inner);
  across(0, &here);
  across(1, &below);
  for (int y = 1; y + 1 < rows; ++y) {
    above.swap(here);
    here.swap(below);
    across(y + 1, &below);
    neighbourhood = above.max(here).max(below);
    if (candidates.size() < count + inner) candidates.resize(2 * (count + inner));
    const float* e = eigenvalues.ptr<float>(y) + 1;
    const uchar* allowed = mask.ptr<uchar>(y) + 1;
    for (Eigen::Index x = 0; x < inner; ++x) {
      const float v = e[x];
      candidates[count] = {v, y * cols + static_cast<int>(x) + 1};
      count += v > threshold && v >= neighbourhood(x) && allowed[x];
    }
  }
  candidates.resize(count);
  // Strongest first; ties as cv::goodFeaturesToTrack orders them (the later pixel first).
  const auto stronger = [](const Candidate& p, const Candidate& q) {
    return p.value > q.value || (p.value == q.value && p.offset > q.offset);
  };

  // Kept when no stronger kept corner is nearer than min_distance; a grid of min_distance cells
  // finds the kept corners that might be.
  const int cell = static_cast<int>(std::lround(min_distance));
  const int grid_cols = (cols + cell - 1) / cell, grid_rows = (rows + cell - 1) / cell;
  std::vector<std::vector<cv::Point2f>> grid(static_cast<size_t>(grid_cols) * grid_rows);
  const float min_squared = static_cast<float>(min_distance * min_distance);
  std::vector<cv::Point2f> corners;
  const auto keep_if_apart = [&](const Candidate& candidate) {
    const int y = candidate.offset / cols, x = candidate.offset % cols;
    const int cx = x / cell, cy = y / cell;
    for (int gy = std::max(0, cy - 1); gy <= std::min(grid_rows - 1, cy + 1); ++gy)
      for (int gx = std::max(0, cx - 1); gx <= std::min(grid_cols - 1, cx + 1); ++gx)
        for (const cv::Point2f& kept : grid[static_cast<size_t>(gy) * grid_cols + gx]) {
          const float ddx = x - kept.x, ddy = y - kept.y;
          if (ddx * ddx + ddy * ddy < min_squared) return;
        }
    const cv::Point2f corner(static_cast<float>(x), static_cast<float>(y));
    grid[static_cast<size_t>(cy) * grid_cols + cx].push_back(corner);
    corners.push_back(corner);
  };
  // Sorted a batch at a time: the strongest few hundred candidates usually give max_corners,
  // and sorting all of them would cost more than finding them.
  const std::ptrdiff_t batch = 8 * static_cast<std::ptrdiff_t>(max_corners);
  for (auto begin = candidates.begin();
       begin != candidates.end() && static_cast<int>(corners.size()) < max_corners;) {
    const auto end = candidates.end() - begin > batch ? begin + batch : candidates.end();
    std::nth_element(begin, end, candidates.end(), stronger);
    std::sort(begin, end, stronger);
    for (; begin != end && static_cast<int>(corners.size()) < max_corners; ++begin)
      keep_if_apart(*begin);
    begin = end;
  }
  return corners;
}

}  // namespace omnisfm::track
