#include "omnisfm/track/patch_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace omnisfm::track {
namespace {

// Contrast below this (grey levels, weighted standard deviation) is no texture.
constexpr double kMinContrast = 1.0;

}  // namespace

bool ReferencePatch::extract(const cv::Mat& image, const Eigen::Vector2d& feature, int half_size,
                             ReferencePatch* patch) {
  CV_Assert(image.type() == CV_32FC1 && half_size >= 1);
  const int cx = static_cast<int>(std::lround(feature.x()));
  const int cy = static_cast<int>(std::lround(feature.y()));
  // One pixel beyond the patch, for central-difference gradients.
  const int reach = half_size + 1;
  if (!(cx - reach >= 0 && cy - reach >= 0 && cx + reach < image.cols && cy + reach < image.rows))
    return false;

  ReferencePatch p;
  p.half_size_ = half_size;
  const int side = 2 * half_size + 1;
  const Eigen::Index count = side * side;
  p.offsets_x_.resize(count);
  p.offsets_y_.resize(count);
  p.weights_.resize(count);
  p.values_.resize(count);
  const Eigen::Vector2d phase(cx - feature.x(), cy - feature.y());
  const double sigma = half_size;
  // The Gaussian window is separable: one exponential per row and per column.
  Eigen::ArrayXd column_weight(side), row_weight(side);
  for (int i = 0; i < side; ++i) {
    const double u = i - half_size + phase.x(), v = i - half_size + phase.y();
    column_weight(i) = std::exp(-u * u / (2 * sigma * sigma));
    row_weight(i) = std::exp(-v * v / (2 * sigma * sigma));
  }
  const double weight_sum = column_weight.sum() * row_weight.sum();
  Eigen::Index k = 0;
  for (int y = -half_size; y <= half_size; ++y)
    for (int x = -half_size; x <= half_size; ++x, ++k) {
      p.offsets_x_(k) = static_cast<float>(x + phase.x());
      p.offsets_y_(k) = static_cast<float>(y + phase.y());
      p.weights_(k) =
          static_cast<float>(column_weight(x + half_size) * row_weight(y + half_size) / weight_sum);
      p.values_(k) = image.at<float>(cy + y, cx + x);
    }
  const double mean = (p.weights_.cast<double>() * p.values_.cast<double>()).sum();
  p.values_ = (p.values_.cast<double>() - mean).cast<float>();
  p.norm_ = std::sqrt((p.weights_.cast<double>() * p.values_.cast<double>().square()).sum());
  if (p.norm_ < kMinContrast) return false;

  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  p.steepest_.resize(count, 6);
  k = 0;
  for (int y = -half_size; y <= half_size; ++y)
    for (int x = -half_size; x <= half_size; ++x, ++k) {
      const double gx =
          0.5 * (image.at<float>(cy + y, cx + x + 1) - image.at<float>(cy + y, cx + x - 1));
      const double gy =
          0.5 * (image.at<float>(cy + y + 1, cx + x) - image.at<float>(cy + y - 1, cx + x));
      const double u = p.offsets_x_(k), v = p.offsets_y_(k);
      Eigen::Matrix<double, 6, 1> sd;
      sd << gx * u, gx * v, gy * u, gy * v, gx, gy;
      hessian += p.weights_(k) * sd * sd.transpose();
      p.steepest_.row(k) = (p.weights_(k) * sd).cast<float>().transpose();
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(hessian,
                                                                         Eigen::EigenvaluesOnly);
  if (!(eigen.eigenvalues()(0) > 1e-9 * eigen.eigenvalues()(5))) return false;
  p.hessian_inverse_ = hessian.inverse();
  *patch = std::move(p);
  return true;
}

double ReferencePatch::sample(const cv::Mat& image, const AffineWarp& warp,
                              Samples* samples) const {
  const int side = 2 * half_size_ + 1;
  const Eigen::Index count = values_.size();
  // The patch's corners bound it (an affine image of a square is a parallelogram).
  const float x_limit = image.cols - 1.0f, y_limit = image.rows - 1.0f;
  for (const Eigen::Index corner :
       {Eigen::Index{0}, Eigen::Index(side - 1), count - side, count - 1}) {
    const Eigen::Vector2d at =
        warp.A * Eigen::Vector2d(offsets_x_(corner), offsets_y_(corner)) + warp.b;
    if (!(at.x() >= 0 && at.y() >= 0 && at.x() < x_limit && at.y() < y_limit)) return -1;
  }
  // Bilinear sampling as whole-patch array operations, which vectorise; only the reads of the
  // four neighbours of each sample are done one at a time.
  Samples& s = *samples;
  s.resize(count);
  const Eigen::Matrix2f A = warp.A.cast<float>();
  const Eigen::Vector2f b = warp.b.cast<float>();
  auto x = s.col(kX), y = s.col(kY);
  x = A(0, 0) * offsets_x_ + A(0, 1) * offsets_y_ + b.x();
  y = A(1, 0) * offsets_x_ + A(1, 1) * offsets_y_ + b.y();
  const int step = static_cast<int>(image.step1());
  // Inside the image (checked above), so truncation is the floor.
  s.index = y.cast<int>() * step + x.cast<int>();
  const float* data = image.ptr<float>();
  auto top_left = s.col(kTopLeft), top_right = s.col(kTopRight);
  auto bottom_left = s.col(kBottomLeft), bottom_right = s.col(kBottomRight);
  for (Eigen::Index k = 0; k < count; ++k) {
    const float* p = data + s.index(k);
    top_left(k) = p[0];
    top_right(k) = p[1];
    bottom_left(k) = p[step];
    bottom_right(k) = p[step + 1];
  }
  const auto fx = x - x.cast<int>().cast<float>();
  const auto fy = y - y.cast<int>().cast<float>();
  auto values = s.col(kValue);
  // The lerps overwrite the corners, which they no longer need.
  top_left += fx * (top_right - top_left);
  bottom_left += fx * (bottom_right - bottom_left);
  values = top_left + fy * (bottom_left - top_left);
  auto weighted = s.col(kTopRight);
  weighted = weights_ * values;
  const double sum_wv = weighted.sum();
  const double sum_wvv = (weighted * values).sum();
  const double sum_wvt = (weighted * values_).sum();
  // Weights sum to 1 and the template has weighted mean 0, so sum w (v - m) t = sum w v t.
  const double m = sum_wv;
  const double variance = std::max(0.0, sum_wvv - m * m);
  const double norm = std::sqrt(variance);
  s.mean = m;
  s.gain = norm > 0 ? norm_ / norm : 0;
  return norm > 0 ? sum_wvt / (norm * norm_) : 0;
}

double ReferencePatch::ncc(const cv::Mat& image, const AffineWarp& warp) const {
  Samples samples;
  return sample(image, warp, &samples);
}

AlignmentResult ReferencePatch::align(const cv::Mat& image, AffineWarp* warp, int max_iterations,
                                      double step_tolerance_px) const {
  CV_Assert(image.type() == CV_32FC1 && !empty());
  AlignmentResult result;
  Samples samples;
  for (result.iterations = 1; result.iterations <= max_iterations; ++result.iterations) {
    result.ncc = sample(image, *warp, &samples);
    if (result.ncc == -1) return result;
    const float m = static_cast<float>(samples.mean), g = static_cast<float>(samples.gain);
    // The residuals, then one dot product per parameter: both vectorise.
    auto residuals = samples.col(kValue);
    residuals = (residuals - m) * g - values_;
    const Eigen::Matrix<float, 6, 1> gradient = steepest_.transpose() * residuals.matrix();
    const Eigen::Matrix<double, 6, 1> dp = hessian_inverse_ * gradient.cast<double>();

    // Inverse composition: W <- W o W(dp)^-1.
    Eigen::Matrix2d A_dp;
    A_dp << 1 + dp(0), dp(1), dp(2), 1 + dp(3);
    if (!(std::abs(A_dp.determinant()) > 1e-6)) return result;
    const Eigen::Matrix2d A = warp->A * A_dp.inverse();
    const Eigen::Vector2d step = A * dp.tail<2>();
    warp->A = A;
    warp->b -= step;
    const double det = A.determinant();
    if (!(det > 0.25 && det < 4)) return result;
    // The correlation measured before this last, tiny step stands for the one after it: at
    // the optimum it changes only with the square of the step, and sampling again would cost a
    // fifth of the alignment.
    if (step.norm() < step_tolerance_px) {
      result.converged = true;
      return result;
    }
  }
  result.iterations = max_iterations;
  return result;
}

}  // namespace omnisfm::track
