#include "omnisfm/track/feature_detector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "omnisfm/track/valid_region.h"

namespace omnisfm::track {
namespace {

// The ring of `p` from every pixel of the region: equal-area rings between the nearest and the
// farthest pixel from the region's centre.
int ring_of_every_pixel(const cv::Mat& region, int rings, const cv::Point2f& p) {
  const cv::Point2d centre = region_centre(region);
  double r2_min = 1e300, r2_max = 0;
  for (int y = 0; y < region.rows; ++y)
    for (int x = 0; x < region.cols; ++x)
      if (region.at<uchar>(y, x)) {
        const double r2 = (x - centre.x) * (x - centre.x) + (y - centre.y) * (y - centre.y);
        r2_min = std::min(r2_min, r2);
        r2_max = std::max(r2_max, r2);
      }
  const double r2 = (p.x - centre.x) * (p.x - centre.x) + (p.y - centre.y) * (p.y - centre.y);
  int ring = 0;
  while (ring + 1 < rings && r2 > r2_min + (r2_max - r2_min) * (ring + 1) / rings) ++ring;
  return ring;
}

// Regions a mirror's image can leave, and a few it does not: an annulus, one cut by the image's
// edge, a disc, a crescent, and an annulus whose hole is not round.
std::vector<cv::Mat> regions() {
  std::vector<cv::Mat> all;
  const auto annulus = [](cv::Size size, cv::Point centre, int inner, int outer) {
    cv::Mat r = cv::Mat::zeros(size, CV_8UC1);
    cv::circle(r, centre, outer, 255, cv::FILLED);
    cv::circle(r, centre, inner, 0, cv::FILLED);
    return r;
  };
  all.push_back(annulus({301, 241}, {150, 120}, 30, 110));
  all.push_back(annulus({200, 160}, {120, 70}, 25, 100));
  all.push_back(annulus({181, 181}, {90, 90}, 0, 80));
  cv::Mat crescent = annulus({240, 200}, {120, 100}, 0, 90);
  cv::circle(crescent, {150, 100}, 80, 0, cv::FILLED);
  all.push_back(crescent);
  all.push_back(annulus({257, 199}, {128, 99}, 40, 95)(cv::Rect(3, 0, 250, 199)).clone());
  // Its hole widened leftwards: the nearest pixels lie right of the centre only.
  cv::Mat widened = annulus({301, 241}, {150, 120}, 30, 110);
  widened(cv::Rect(60, 80, 91, 81)).setTo(0);
  all.push_back(widened);
  return all;
}

TEST(FeatureDetector, RingsAsEveryPixelOfTheRegionGivesThem) {
  std::mt19937 rng(3);
  for (const cv::Mat& region : regions()) {
    TrackerSettings settings;
    settings.rings = 4;
    settings.sectors = 6;
    const FeatureDetector detector(region, settings);
    std::uniform_real_distribution<float> x(0, region.cols - 1), y(0, region.rows - 1);
    std::vector<int> per_ring(settings.rings, 0);
    for (int i = 0; i < 400; ++i) {
      const cv::Point2f p(x(rng), y(rng));
      const int expected = ring_of_every_pixel(region, settings.rings, p);
      ASSERT_EQ(detector.cell(p) / settings.sectors, expected)
          << "region " << region.size() << " at " << p;
      ++per_ring[expected];
    }
    for (int ring = 0; ring < settings.rings; ++ring)
      EXPECT_GT(per_ring[ring], 0) << "region " << region.size() << " ring " << ring;
  }
}

// Corners are found on a half-size image, and only where the region allows them at full size.
TEST(FeatureDetector, FindsCornersOnlyInTheRegion) {
  cv::Mat image(260, 320, CV_8UC1);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> grey(0, 255);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) image.at<uchar>(y, x) = static_cast<uchar>(grey(rng));
  cv::GaussianBlur(image, image, cv::Size(5, 5), 1.5);
  for (const cv::Mat& region : regions()) {
    TrackerSettings settings;
    ASSERT_EQ(settings.detection_level, 1);
    const FeatureDetector detector(region, settings);
    cv::Mat level;
    cv::pyrDown(image(cv::Rect(0, 0, region.cols, region.rows)), level);
    const std::vector<cv::Point2f> corners = detector.corners(level, {});
    EXPECT_GT(corners.size(), 20u) << region.size();
    for (const cv::Point2f& c : corners) {
      const int x = static_cast<int>(c.x), y = static_cast<int>(c.y);
      ASSERT_TRUE(x >= 0 && y >= 0 && x < region.cols && y < region.rows) << c;
      EXPECT_TRUE(region.at<uchar>(y, x)) << region.size() << " " << c;
    }
  }
}

}  // namespace
}  // namespace omnisfm::track
