#include "square_correlation.h"

#include <cmath>

namespace omnisfm::track {

SquareCorrelation::SquareCorrelation(const cv::Mat& image, const cv::Point& centre, int half)
    : image_(image), half_(half) {
  CV_Assert(image.type() == CV_32FC1 && half >= 0 && fits(centre));
  const int side = 2 * half + 1;
  zero_mean_.reserve(static_cast<size_t>(side) * side);
  double sum = 0;
  for (int y = -half; y <= half; ++y) {
    const float* row = image.ptr<float>(centre.y + y) + centre.x;
    for (int x = -half; x <= half; ++x) {
      zero_mean_.push_back(row[x]);
      sum += row[x];
    }
  }
  mean_ = static_cast<float>(sum / zero_mean_.size());
  for (float& v : zero_mean_) {
    v -= mean_;
    norm_squared_ += static_cast<double>(v) * v;
  }
}

bool SquareCorrelation::fits(const cv::Point& centre) const {
  return centre.x - half_ >= 0 && centre.y - half_ >= 0 && centre.x + half_ < image_.cols &&
         centre.y + half_ < image_.rows;
}

double SquareCorrelation::at(const cv::Point& centre) const {
  CV_Assert(fits(centre));
  const int side = 2 * half_ + 1;
  // The variance is a difference of two sums: of the pixels less the first square's mean (a
  // little cancels), per row in float, across rows in double.
  double sum = 0, sum_squares = 0, product = 0;
  const float* t = zero_mean_.data();
  for (int y = -half_; y <= half_; ++y, t += side) {
    const float* row = image_.ptr<float>(centre.y + y) + centre.x - half_;
    float row_sum = 0, row_squares = 0, row_product = 0;
    for (int x = 0; x < side; ++x) {
      const float v = row[x] - mean_;
      row_sum += v;
      row_squares += v * v;
      row_product += v * t[x];
    }
    sum += row_sum;
    sum_squares += row_squares;
    product += row_product;
  }
  // With the first square zero-mean, sum t (v - mean v) = sum t (v - any constant).
  const double variance = sum_squares - sum * sum / (side * side);
  // Flat: no contrast beyond the rounding of the sums.
  constexpr double kRounding = 1e-5;
  if (!(variance > kRounding * sum_squares) || !(norm_squared_ > 0)) return 0;
  return product / std::sqrt(norm_squared_ * variance);
}

}  // namespace omnisfm::track
