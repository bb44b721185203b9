#include "../src/gaussian_blur.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace omnisfm::track {
namespace {

cv::Mat opencv_blurred(const cv::Mat& grey, double sigma) {
  const int half = std::max(1, static_cast<int>(3 * sigma));
  const cv::Mat kernel = cv::getGaussianKernel(2 * half + 1, sigma, CV_32F);
  cv::Mat blurred;
  cv::sepFilter2D(grey, blurred, CV_32F, kernel, kernel, cv::Point(-1, -1), 0,
                  cv::BORDER_REFLECT_101);
  return blurred;
}

cv::Mat noise(int rows, int cols, int seed) {
  cv::Mat grey(rows, cols, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(grey, cv::RNG::UNIFORM, 0, 256);
  return grey;
}

// OpenCV's separable filter with the same taps and border, on images from one pixel to wider
// than a register, and kernels from 3 to 13 taps: within float rounding of 255-level sums (6e-5
// at most, measured).
TEST(GaussianBlur, IsOpenCvsSeparableFilter) {
  int seed = 0;
  for (const double sigma : {0.3, 0.5, 1.0, 2.0})
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(2, 3), cv::Size(5, 1), cv::Size(17, 9),
                                cv::Size(64, 48), cv::Size(701, 333)}) {
      const cv::Mat grey = noise(size.height, size.width, ++seed);
      const cv::Mat ours = gaussian_blurred_float(grey, sigma);
      ASSERT_EQ(ours.type(), CV_32FC1);
      ASSERT_EQ(ours.size(), grey.size());
      EXPECT_LE(cv::norm(ours, opencv_blurred(grey, sigma), cv::NORM_INF), 2e-4)
          << "sigma " << sigma << ", " << size;
    }
}

// A region of interest (rows not contiguous) is blurred as a copy of it would be: its own pixels,
// reflected at its own edges (OpenCV's filters with BORDER_ISOLATED), its parent's unread.
TEST(GaussianBlur, ARegionOfInterestReflectsAtItsOwnEdges) {
  const cv::Mat grey = noise(100, 120, 7);
  const cv::Mat part = grey(cv::Rect(10, 20, 50, 40));
  const cv::Mat blurred = gaussian_blurred_float(part, 0.5);
  EXPECT_LE(cv::norm(blurred, opencv_blurred(part.clone(), 0.5), cv::NORM_INF), 2e-4);
  cv::Mat isolated;
  const cv::Mat kernel = cv::getGaussianKernel(3, 0.5, CV_32F);
  cv::sepFilter2D(part, isolated, CV_32F, kernel, kernel, cv::Point(-1, -1), 0,
                  cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED);
  EXPECT_LE(cv::norm(blurred, isolated, cv::NORM_INF), 2e-4);
  // Without BORDER_ISOLATED OpenCV reads the parent's pixels beyond the edges: its edges differ.
  EXPECT_GT(cv::norm(blurred, opencv_blurred(part, 0.5), cv::NORM_INF), 1);
}

TEST(GaussianBlur, KeepsAConstantImageConstant) {
  const cv::Mat grey(31, 29, CV_8UC1, cv::Scalar(200));
  const cv::Mat blurred = gaussian_blurred_float(grey, 0.5);
  double low, high;
  cv::minMaxLoc(blurred, &low, &high);
  EXPECT_NEAR(low, 200, 1e-3);
  EXPECT_NEAR(high, 200, 1e-3);
}

}  // namespace
}  // namespace omnisfm::track
