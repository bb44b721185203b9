#include "../src/shi_tomasi.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "synthetic_images.h"

namespace omnisfm::track {
namespace {

// A textured 8-bit image, part of a larger one (so that filters see real pixels past its
// edges, as the detector's region of interest does), and a mask with a hole and a margin.
struct Scene {
  cv::Mat whole, image, mask;
};

Scene scene(unsigned seed) {
  Scene s;
  cv::Mat noise(260, 340, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 2.0);
  const testing::WaveTexture texture(seed);
  cv::Mat waves = texture.image(340, 260, Eigen::Matrix2d::Identity() * 0.7, {3, 5});
  cv::addWeighted(noise, 2.0, waves, 0.5, -100, s.whole);
  s.image = s.whole(cv::Rect(10, 7, 300, 240));
  s.mask = cv::Mat(s.image.size(), CV_8UC1, cv::Scalar(255));
  cv::circle(s.mask, {150, 120}, 40, 0, cv::FILLED);
  s.mask.colRange(0, 4).setTo(0);
  return s;
}

// The same corners in the same order as OpenCV's goodFeaturesToTrack, which the tracker used
// before: only float rounding (OpenCV's box filter sums in double) could swap two corners of
// equal strength, and on these images none does.
TEST(ShiTomasi, FindsTheCornersOfGoodFeaturesToTrack) {
  for (const unsigned seed : {1u, 2u, 3u})
    for (const double min_distance : {1.0, 4.0, 8.0})
      // Few corners (sorted in several batches), many, and more than there are.
      for (const int max_corners : {20, 300, 100000}) {
        const Scene s = scene(seed);
        std::vector<cv::Point2f> expected;
        cv::goodFeaturesToTrack(s.image, expected, max_corners, 0.01, min_distance, s.mask, 3);
        const std::vector<cv::Point2f> found =
            shi_tomasi_corners(s.image, max_corners, 0.01, min_distance, s.mask);
        ASSERT_EQ(found.size(), expected.size()) << seed << " " << min_distance;
        if (max_corners == 100000) {
          EXPECT_GT(found.size(), 300u);
        }
        EXPECT_EQ(found, expected) << seed << " " << min_distance << " " << max_corners;
        for (const cv::Point2f& p : found) EXPECT_TRUE(s.mask.at<uchar>(p) != 0);
      }
}

TEST(ShiTomasi, FindsNothingOnAFlatImage) {
  const cv::Mat flat(50, 60, CV_8UC1, cv::Scalar(90));
  const cv::Mat mask(flat.size(), CV_8UC1, cv::Scalar(255));
  EXPECT_TRUE(shi_tomasi_corners(flat, 10, 0.01, 5, mask).empty());
}

}  // namespace
}  // namespace omnisfm::track
