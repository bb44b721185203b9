#include "square_correlation.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "also_for_avx2.h"

namespace omnisfm::track {
namespace {

// Eight floats: one AVX register, two SSE ones where the processor has no AVX2.
using Wide = float __attribute__((vector_size(32)));
constexpr int kWide = 8;

}  // namespace

SquareCorrelation::SquareCorrelation(const cv::Mat& image, const cv::Point& centre, int half)
    : image_(image), half_(half) {
  CV_Assert(image.type() == CV_32FC1 && half >= 0 && fits(image, centre, half));
  const int side = 2 * half + 1;
  padded_side_ = (side + kWide - 1) / kWide * kWide;
  mask_.assign(padded_side_, 0.0f);
  std::fill(mask_.begin(), mask_.begin() + side, 1.0f);
  double sum = 0;
  for (int y = -half; y <= half; ++y) {
    const float* row = image.ptr<float>(centre.y + y) + centre.x;
    for (int x = -half; x <= half; ++x) sum += row[x];
  }
  const float mean = static_cast<float>(sum / (side * side));
  zero_mean_.assign(static_cast<size_t>(padded_side_) * side, 0.0f);
  for (int y = 0; y < side; ++y) {
    const float* row = image.ptr<float>(centre.y - half + y) + centre.x - half;
    for (int x = 0; x < side; ++x) {
      const float v = row[x] - mean;
      zero_mean_[static_cast<size_t>(y) * padded_side_ + x] = v;
      norm_squared_ += static_cast<double>(v) * v;
    }
  }
}

bool SquareCorrelation::fits(const cv::Mat& image, const cv::Point& centre, int half) {
  return centre.x - half >= 0 && centre.y - half >= 0 && centre.x + half < image.cols &&
         centre.y + half < image.rows;
}

namespace {

// The sums of v, v^2 and v t over the square of side 2 half + 1 about `centre`, v the pixels less
// the centre pixel and t the first square's zero-mean rows (padded_side apart, `mask` zeroing
// their padding). A free function: Clang builds no processor variants of a member function.
struct Sums {
  double values = 0, squares = 0, products = 0;
};
OMNISFM_ALSO_FOR_AVX2 Sums sums_about(const cv::Mat& image, const cv::Point& centre, int half,
                                      int padded_side, const float* zero_mean, const float* mask) {
  const int side = 2 * half + 1;
  // kWide pixels at a time in float. Each row is read in whole registers, the template's padding
  // and `mask` zeroing what lies beyond the square, where the image has that many more columns;
  // at its right edge the last pixels are added one by one.
  const bool whole_registers = centre.x - half + padded_side <= image.cols;
  const int in_registers = whole_registers ? padded_side : side / kWide * kWide;
  const float reference = image.ptr<float>(centre.y)[centre.x];
  Wide sum = {}, squares = {}, product = {};
  const float* t = zero_mean;
  for (int y = -half; y <= half; ++y, t += padded_side) {
    const float* row = image.ptr<float>(centre.y + y) + centre.x - half;
    for (int x = 0; x < in_registers; x += kWide) {
      Wide pixels, lanes_mask, first;
      std::memcpy(&pixels, row + x, sizeof pixels);
      std::memcpy(&lanes_mask, mask + x, sizeof lanes_mask);
      std::memcpy(&first, t + x, sizeof first);
      const Wide v = (pixels - reference) * lanes_mask;
      sum += v;
      squares += v * v;
      product += v * first;
    }
    for (int x = in_registers; x < side; ++x) {
      const float v = row[x] - reference;
      sum[0] += v;
      squares[0] += v * v;
      product[0] += v * t[x];
    }
  }
  Sums total;
  for (int lane = 0; lane < kWide; ++lane) {
    total.values += sum[lane];
    total.squares += squares[lane];
    total.products += product[lane];
  }
  return total;
}

}  // namespace

double SquareCorrelation::at(const cv::Point& centre) const {
  CV_Assert(fits(centre));
  const int side = 2 * half_ + 1;
  // Sums of the pixels less the square's own centre pixel: the variance is a difference of two
  // sums, which then stay of the order of the square's own contrast.
  const Sums s = sums_about(image_, centre, half_, padded_side_, zero_mean_.data(), mask_.data());
  // With the first square zero-mean, sum t (v - mean v) = sum t (v - any constant).
  const double variance = s.squares - s.values * s.values / (side * side);
  // Flat: no contrast beyond the rounding of the sums.
  constexpr double kRounding = 1e-5;
  if (!(variance > kRounding * s.squares) || !(norm_squared_ > 0)) return 0;
  return std::clamp(s.products / std::sqrt(norm_squared_ * variance), -1.0, 1.0);
}

}  // namespace omnisfm::track
