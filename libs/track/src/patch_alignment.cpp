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
  const Eigen::Vector2d phase(cx - feature.x(), cy - feature.y());
  const double sigma = half_size;
  double weight_sum = 0;
  for (int y = -half_size; y <= half_size; ++y)
    for (int x = -half_size; x <= half_size; ++x) {
      const Eigen::Vector2d offset = Eigen::Vector2d(x, y) + phase;
      p.offsets_.push_back(offset.cast<float>());
      p.weights_.push_back(
          static_cast<float>(std::exp(-offset.squaredNorm() / (2 * sigma * sigma))));
      weight_sum += p.weights_.back();
      p.values_.push_back(image.at<float>(cy + y, cx + x));
    }
  double mean = 0;
  for (size_t k = 0; k < p.values_.size(); ++k) {
    p.weights_[k] = static_cast<float>(p.weights_[k] / weight_sum);
    mean += p.weights_[k] * p.values_[k];
  }
  double variance = 0;
  for (size_t k = 0; k < p.values_.size(); ++k) {
    p.values_[k] = static_cast<float>(p.values_[k] - mean);
    variance += p.weights_[k] * p.values_[k] * p.values_[k];
  }
  p.norm_ = std::sqrt(variance);
  if (p.norm_ < kMinContrast) return false;

  Eigen::Matrix<double, 6, 6> hessian = Eigen::Matrix<double, 6, 6>::Zero();
  size_t k = 0;
  for (int y = -half_size; y <= half_size; ++y)
    for (int x = -half_size; x <= half_size; ++x, ++k) {
      const double gx =
          0.5 * (image.at<float>(cy + y, cx + x + 1) - image.at<float>(cy + y, cx + x - 1));
      const double gy =
          0.5 * (image.at<float>(cy + y + 1, cx + x) - image.at<float>(cy + y - 1, cx + x));
      const double u = p.offsets_[k].x(), v = p.offsets_[k].y();
      Eigen::Matrix<double, 6, 1> sd;
      sd << gx * u, gx * v, gy * u, gy * v, gx, gy;
      hessian += p.weights_[k] * sd * sd.transpose();
      p.steepest_.push_back((p.weights_[k] * sd).cast<float>());
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(hessian);
  if (!(eigen.eigenvalues()(0) > 1e-9 * eigen.eigenvalues()(5))) return false;
  p.hessian_inverse_ = hessian.inverse();
  *patch = std::move(p);
  return true;
}

double ReferencePatch::sample(const cv::Mat& image, const AffineWarp& warp,
                              std::vector<float>* values, double* mean, double* gain) const {
  const int side = 2 * half_size_ + 1;
  values->resize(offsets_.size());
  // The patch's corners bound it (an affine image of a square is a parallelogram).
  const float x_limit = image.cols - 1.0f, y_limit = image.rows - 1.0f;
  for (const size_t corner :
       {size_t{0}, size_t(side - 1), offsets_.size() - side, offsets_.size() - 1}) {
    const Eigen::Vector2d at = warp.A * offsets_[corner].cast<double>() + warp.b;
    if (!(at.x() >= 0 && at.y() >= 0 && at.x() < x_limit && at.y() < y_limit)) return -1;
  }
  const Eigen::Matrix2f A = warp.A.cast<float>();
  const Eigen::Vector2f b = warp.b.cast<float>();
  const size_t step = image.step1();
  const float* data = image.ptr<float>();
  float sum_wv = 0, sum_wvv = 0, sum_wvt = 0;
  for (int row = 0; row < side; ++row) {
    const size_t first = static_cast<size_t>(row) * side;
    Eigen::Vector2f at = A * offsets_[first] + b;
    const Eigen::Vector2f along = A.col(0);
    for (int k = 0; k < side; ++k, at += along) {
      const int x0 = static_cast<int>(at.x()), y0 = static_cast<int>(at.y());
      const float fx = at.x() - x0, fy = at.y() - y0;
      const float* p = data + y0 * step + x0;
      const float top = p[0] + fx * (p[1] - p[0]);
      const float bottom = p[step] + fx * (p[step + 1] - p[step]);
      const float v = top + fy * (bottom - top);
      (*values)[first + k] = v;
      const float w = weights_[first + k];
      sum_wv += w * v;
      sum_wvv += w * v * v;
      sum_wvt += w * v * values_[first + k];
    }
  }
  // Weights sum to 1 and the template has weighted mean 0, so sum w (v - m) t = sum w v t.
  const double m = sum_wv;
  const double variance = std::max(0.0, static_cast<double>(sum_wvv) - m * m);
  const double norm = std::sqrt(variance);
  *mean = m;
  *gain = norm > 0 ? norm_ / norm : 0;
  return norm > 0 ? sum_wvt / (norm * norm_) : 0;
}

double ReferencePatch::ncc(const cv::Mat& image, const AffineWarp& warp) const {
  std::vector<float> values;
  double mean, gain;
  return sample(image, warp, &values, &mean, &gain);
}

AlignmentResult ReferencePatch::align(const cv::Mat& image, AffineWarp* warp, int max_iterations,
                                      double step_tolerance_px) const {
  CV_Assert(image.type() == CV_32FC1 && !empty());
  AlignmentResult result;
  std::vector<float> values;
  for (result.iterations = 1; result.iterations <= max_iterations; ++result.iterations) {
    double mean, gain;
    result.ncc = sample(image, *warp, &values, &mean, &gain);
    if (result.ncc == -1) return result;
    const float m = static_cast<float>(mean), g = static_cast<float>(gain);
    Eigen::Matrix<float, 6, 1> gradient = Eigen::Matrix<float, 6, 1>::Zero();
    for (size_t k = 0; k < values.size(); ++k)
      gradient += steepest_[k] * ((values[k] - m) * g - values_[k]);
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
    if (step.norm() < step_tolerance_px) {
      result.ncc = ncc(image, *warp);
      result.converged = result.ncc > -1;
      return result;
    }
  }
  result.iterations = max_iterations;
  return result;
}

}  // namespace omnisfm::track
