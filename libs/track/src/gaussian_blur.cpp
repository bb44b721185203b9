#include "gaussian_blur.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "also_for_avx2.h"

namespace omnisfm::track {
namespace {

// Fills the `half` places on each side of row[0, cols) with the row's pixels reflected about its
// end pixels.
void reflect_ends(float* row, int cols, int half) {
  for (int i = 1; i <= half; ++i) {
    row[-i] = row[cv::borderInterpolate(-i, cols, cv::BORDER_REFLECT_101)];
    row[cols - 1 + i] = row[cv::borderInterpolate(cols - 1 + i, cols, cv::BORDER_REFLECT_101)];
  }
}

}  // namespace

OMNISFM_ALSO_FOR_AVX2 cv::Mat gaussian_blurred_float(const cv::Mat& grey, double sigma) {
  CV_Assert(grey.type() == CV_8UC1 && !grey.empty() && sigma > 0);
  const int half = std::max(1, static_cast<int>(3 * sigma));
  const cv::Mat taps = cv::getGaussianKernel(2 * half + 1, sigma, CV_32F);
  // Symmetric: weight[i] for the pixels i away on either side.
  std::vector<float> weight(half + 1);
  for (int i = 0; i <= half; ++i) weight[i] = taps.at<float>(half + i);
  const int rows = grey.rows, cols = grey.cols;
  cv::Mat blurred(rows, cols, CV_32F);
  // One row blurred down the columns, with `half` reflected pixels on each side.
  std::vector<float> padded(cols + 2 * half);
  float* column_sums = padded.data() + half;
  std::vector<const uchar*> around(2 * half + 1);
  for (int y = 0; y < rows; ++y) {
    for (int i = -half; i <= half; ++i)
      around[i + half] =
          grey.ptr<uchar>(cv::borderInterpolate(y + i, rows, cv::BORDER_REFLECT_101));
    float* __restrict sums = column_sums;
    float* __restrict out = blurred.ptr<float>(y);
    if (half == 1) {  // the tracker's 0.5-pixel blur: each pass one store per pixel
      const uchar* __restrict above = around[0];
      const uchar* __restrict centre = around[1];
      const uchar* __restrict below = around[2];
      const float w0 = weight[0], w1 = weight[1];
      for (int x = 0; x < cols; ++x)
        sums[x] = w0 * centre[x] + w1 * static_cast<float>(above[x] + below[x]);
      reflect_ends(column_sums, cols, half);
      for (int x = 0; x < cols; ++x) out[x] = w0 * sums[x] + w1 * (sums[x - 1] + sums[x + 1]);
      continue;
    }
    // Loops over whole rows, the taps outside: each vectorises.
    const uchar* __restrict centre = around[half];
    for (int x = 0; x < cols; ++x) sums[x] = weight[0] * centre[x];
    for (int i = 1; i <= half; ++i) {
      const uchar* __restrict above = around[half - i];
      const uchar* __restrict below = around[half + i];
      const float w = weight[i];
      for (int x = 0; x < cols; ++x) sums[x] += w * static_cast<float>(above[x] + below[x]);
    }
    reflect_ends(column_sums, cols, half);
    for (int x = 0; x < cols; ++x) out[x] = weight[0] * sums[x];
    for (int i = 1; i <= half; ++i) {
      const float w = weight[i];
      for (int x = 0; x < cols; ++x) out[x] += w * (sums[x - i] + sums[x + i]);
    }
  }
  return blurred;
}

}  // namespace omnisfm::track
