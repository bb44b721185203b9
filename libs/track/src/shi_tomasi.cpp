#include "shi_tomasi.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "float_lanes.h"

namespace omnisfm::track {
namespace {

// Row i of n with OpenCV's default border (reflected about the edge pixel), as the Sobel filter
// and the box filter in cv::cornerMinEigenVal use.
int reflect_101(int i, int n) { return cv::borderInterpolate(i, n, cv::BORDER_REFLECT_101); }

using AllowedLanes = unsigned char __attribute__((vector_size(kLanes)));
using Flags = int __attribute__((vector_size(16)));  // a comparison's lanes: -1 where true

Lanes max(const Lanes& a, const Lanes& b) { return a > b ? a : b; }

// The smaller eigenvalue per pixel, as cv::cornerMinEigenVal(image, 3, 3) computes it (up to
// float rounding: its box filter sums in double), and in *strongest the largest where `mask` is
// set (0 if none is positive). Rows are padded to a multiple of kLanes, so that every pass is
// whole registers; the padding is computed and never read.
cv::Mat min_eigenvalues(const cv::Mat& image, const cv::Mat& mask, double* strongest) {
  const int rows = image.rows, cols = image.cols;
  const int padded = (cols + kLanes - 1) / kLanes * kLanes;
  // The scale cv::cornerMinEigenVal gives 8-bit images: 1 / (2^(3 - 1) * 3 * 255).
  const double scale = 1.0 / (4 * 3 * 255.0);
  cv::Mat dx_padded(rows, padded, CV_32F), dy_padded(rows, padded, CV_32F);
  cv::Mat dx = dx_padded.colRange(0, cols), dy = dy_padded.colRange(0, cols);
  cv::Sobel(image, dx, CV_32F, 1, 0, 3, scale, 0, cv::BORDER_DEFAULT);
  cv::Sobel(image, dy, CV_32F, 0, 1, 3, scale, 0, cv::BORDER_DEFAULT);
  CV_Assert(dx.data == dx_padded.data && dy.data == dy_padded.data);  // filled in place
  for (int y = 0; y < rows; ++y) {  // finite padding: no slow arithmetic on garbage
    std::fill(dx_padded.ptr<float>(y) + cols, dx_padded.ptr<float>(y) + padded, 0.0f);
    std::fill(dy_padded.ptr<float>(y) + cols, dy_padded.ptr<float>(y) + padded, 0.0f);
  }
  cv::Mat eigenvalues(rows, padded, CV_32F);
  // The moments summed down three rows, with one more column on each side for the sums across.
  std::vector<float> buffers(3 * static_cast<size_t>(padded + 2));
  float* xx = buffers.data() + 1;
  float* xy = xx + padded + 2;
  float* yy = xy + padded + 2;
  std::vector<unsigned char> allowed_row(static_cast<size_t>(padded), 0);
  Lanes best = {};
  for (int y = 0; y < rows; ++y) {
    std::memcpy(allowed_row.data(), mask.ptr<uchar>(y), static_cast<size_t>(cols));
    const float* dx0 = dx_padded.ptr<float>(reflect_101(y - 1, rows));
    const float* dx1 = dx_padded.ptr<float>(y);
    const float* dx2 = dx_padded.ptr<float>(reflect_101(y + 1, rows));
    const float* dy0 = dy_padded.ptr<float>(reflect_101(y - 1, rows));
    const float* dy1 = dy_padded.ptr<float>(y);
    const float* dy2 = dy_padded.ptr<float>(reflect_101(y + 1, rows));
    for (int x = 0; x < padded; x += kLanes) {
      const Lanes gx0 = load(dx0 + x), gx1 = load(dx1 + x), gx2 = load(dx2 + x);
      const Lanes gy0 = load(dy0 + x), gy1 = load(dy1 + x), gy2 = load(dy2 + x);
      store(xx + x, gx0 * gx0 + gx1 * gx1 + gx2 * gx2);
      store(xy + x, gx0 * gy0 + gx1 * gy1 + gx2 * gy2);
      store(yy + x, gy0 * gy0 + gy1 * gy1 + gy2 * gy2);
    }
    for (float* sums : {xx, xy, yy}) {
      sums[-1] = sums[1];
      sums[cols] = sums[cols - 2];
    }
    // As cv::cornerMinEigenVal: with a = xx / 2, c = yy / 2, the smaller eigenvalue of
    // [xx xy; xy yy] is a + c - sqrt((a - c)^2 + xy^2).
    float* out = eigenvalues.ptr<float>(y);
    for (int x = 0; x < padded; x += kLanes) {
      const Lanes a = 0.5f * (load(xx + x - 1) + load(xx + x) + load(xx + x + 1));
      const Lanes b = load(xy + x - 1) + load(xy + x) + load(xy + x + 1);
      const Lanes c = 0.5f * (load(yy + x - 1) + load(yy + x) + load(yy + x + 1));
      const Lanes d = a - c;
      const Lanes r = d * d + b * b;
      // Eigen's square root of a whole register (vector extensions have none).
      Eigen::Array4f root;
      std::memcpy(root.data(), &r, sizeof r);
      root = root.sqrt();
      const Lanes e = (a + c) - load(root.data());
      store(out + x, e);
      AllowedLanes allowed;
      std::memcpy(&allowed, allowed_row.data() + x, sizeof allowed);
      // A vector comparison gives -1 where true.
      const Lanes on = -__builtin_convertvector(allowed != 0, Lanes);
      const Lanes masked = e * on;
      best = best > masked ? best : masked;
    }
  }
  *strongest = 0;
  for (int lane = 0; lane < kLanes; ++lane) *strongest = std::max<double>(*strongest, best[lane]);
  return eigenvalues.colRange(0, cols);
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
  double strongest = 0;
  const cv::Mat eigenvalues = min_eigenvalues(image, mask, &strongest);
  const float threshold = static_cast<float>(strongest * quality_level);

  // Local maxima (of the 3 x 3 neighbourhood) above the threshold, off the outermost pixels:
  // kLanes pixels tested at once, and only the groups that hold one looked at pixel by pixel
  // (most pixels are not local maxima).
  std::vector<Candidate> candidates;
  const auto add = [&](float value, const uchar* allowed, int y, int x) {
    if (allowed[x]) candidates.push_back({value, y * cols + x});
  };
  for (int y = 1; y + 1 < rows; ++y) {
    const float* above = eigenvalues.ptr<float>(y - 1);
    const float* here = eigenvalues.ptr<float>(y);
    const float* below = eigenvalues.ptr<float>(y + 1);
    const uchar* allowed = mask.ptr<uchar>(y);
    int x = 1;
    for (; x + kLanes < cols; x += kLanes) {
      const Lanes v = load(here + x);
      Lanes around = max(load(here + x - 1), load(here + x + 1));
      for (const float* row : {above, below})
        around = max(around, max(max(load(row + x - 1), load(row + x)), load(row + x + 1)));
      const Flags local_maximum = (v > threshold) & (v >= around);
      std::uint64_t halves[2];
      std::memcpy(halves, &local_maximum, sizeof halves);
      if ((halves[0] | halves[1]) == 0) continue;
      for (int lane = 0; lane < kLanes; ++lane)
        if (local_maximum[lane]) add(v[lane], allowed, y, x + lane);
    }
    for (; x + 1 < cols; ++x) {
      const float v = here[x];
      if (v > threshold && v >= here[x - 1] && v >= here[x + 1] && v >= above[x - 1] &&
          v >= above[x] && v >= above[x + 1] && v >= below[x - 1] && v >= below[x] &&
          v >= below[x + 1])
        add(v, allowed, y, x);
    }
  }
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
