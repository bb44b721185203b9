#pragma once
// Test images whose content is known exactly under any affine motion: a band-limited texture,
// a sum of plane waves, sampled at pixel centres after the motion.

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

namespace omnisfm::track::testing {

class WaveTexture {
 public:
  // `waves` plane waves with wavelengths of 6 to 40 texture units, random directions and phases.
  explicit WaveTexture(unsigned seed, int waves = 24) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int i = 0; i < waves; ++i) {
      const double wavelength = 6 + 34 * unit(rng), angle = 2 * M_PI * unit(rng);
      waves_.push_back({Eigen::Vector2d(std::cos(angle), std::sin(angle)) * (2 * M_PI / wavelength),
                        2 * M_PI * unit(rng), 40.0 / std::sqrt(waves)});
    }
  }

  // A texture that repeats every `period` units along both axes (tiles, bricks): each wave's
  // vector on the lattice 2 pi (n, m) / period, wavelengths of 6 to 40 units as above.
  static WaveTexture periodic(unsigned seed, double period, int waves = 24) {
    WaveTexture t(seed, 0);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0, 1);
    const int reach = static_cast<int>(period / 6);
    while (static_cast<int>(t.waves_.size()) < waves) {
      const int n = static_cast<int>(std::lround((2 * unit(rng) - 1) * reach));
      const int m = static_cast<int>(std::lround((2 * unit(rng) - 1) * reach));
      const double wavelength = period / std::hypot(n, m);
      if (!(wavelength >= 6 && wavelength <= 40)) continue;
      t.waves_.push_back({Eigen::Vector2d(n, m) * (2 * M_PI / period), 2 * M_PI * unit(rng),
                          40.0 / std::sqrt(waves)});
    }
    return t;
  }

  double value(const Eigen::Vector2d& uv) const {
    double v = 128;
    for (const Wave& w : waves_) v += w.amplitude * std::sin(w.k.dot(uv) + w.phase);
    return v;
  }

  // An image whose pixel x shows the texture at texture_from_image * x; 8-bit when `quantise`.
  cv::Mat image(int width, int height, const Eigen::Matrix2d& A, const Eigen::Vector2d& b,
                bool quantise = true) const {
    // Each wave's phase is linear in x and y: tabulate its sines per column and per row.
    cv::Mat sum(height, width, CV_64FC1, cv::Scalar(128));
    std::vector<double> sin_x(width), cos_x(width);
    for (const Wave& w : waves_) {
      const Eigen::Vector2d k = A.transpose() * w.k;
      const double offset = w.k.dot(b) + w.phase;
      for (int x = 0; x < width; ++x) {
        sin_x[x] = std::sin(k.x() * x);
        cos_x[x] = std::cos(k.x() * x);
      }
      for (int y = 0; y < height; ++y) {
        const double sin_y = w.amplitude * std::sin(k.y() * y + offset);
        const double cos_y = w.amplitude * std::cos(k.y() * y + offset);
        double* row = sum.ptr<double>(y);
        for (int x = 0; x < width; ++x) row[x] += sin_x[x] * cos_y + cos_x[x] * sin_y;
      }
    }
    cv::Mat out;
    sum.convertTo(out, quantise ? CV_8UC1 : CV_32FC1);
    return out;
  }

 private:
  struct Wave {
    Eigen::Vector2d k;
    double phase, amplitude;
  };
  std::vector<Wave> waves_;
};

}  // namespace omnisfm::track::testing
