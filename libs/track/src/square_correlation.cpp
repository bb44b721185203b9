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

OMNISFM_ALSO_FOR_AVX2 double SquareCorrelation::at(const cv::Point& centre) const {
  CV_Assert(fits(centre));
  const int side = 2 * half_ + 1;
  // Sums of the pixels less the square's own centre pixel (the variance is a difference of two
  // sums, which then stay of the order of the square's own contrast), kWide pixels at a time in
  // float. Each row is read in whole registers, the template's padding and `mask` zeroing what
  // lies beyond the square, where the image has that many more columns; at its right edge the
  // last pixels are added one by one.
  const bool whole_registers = centre.x - half_ + padded_side_ <= image_.cols;
  const int in_registers = whole_registers ? padded_side_ : side / kWide * kWide;
  const float reference = image_.ptr<float>(centre.y)[centre.x];
  Wide sum = {}, squares = {}, product = {};
  const float* t = zero_mean_.data();
  for (int y = -half_; y <= half_; ++y, t += padded_side_) {
    const float* row = image_.ptr<float>(centre.y + y) + centre.x - half_;
    for (int x = 0; x < in_registers; x += kWide) {
      Wide pixels, mask, first;
      std::memcpy(&pixels, row + x, sizeof pixels);
      std::memcpy(&mask, mask_.data() + x, sizeof mask);
      std::memcpy(&first, t + x, sizeof first);
      const Wide v = (pixels - reference) * mask;
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
  double total = 0, total_squares = 0, total_product = 0;
  for (int lane = 0; lane < kWide; ++lane) {
    total += sum[lane];
    total_squares += squares[lane];
    total_product += product[lane];
  }
  // With the first square zero-mean, sum t (v - mean v) = sum t (v - any constant).
  const double variance = total_squares - total * total / (side * side);
  // Flat: no contrast beyond the rounding of the sums.
  constexpr double kRounding = 1e-5;
  if (!(variance > kRounding * total_squares) || !(norm_squared_ > 0)) return 0;
  return std::clamp(total_product / std::sqrt(norm_squared_ * variance), -1.0, 1.0);
}

}  // namespace omnisfm::track
