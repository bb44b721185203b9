#include "omnisfm/track/valid_region.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/pinhole_camera.h"

namespace omnisfm::track {
namespace {

// A 320 x 240 equiangular rig, misaligned so that the region is not a perfect annulus.
camera::CatadioptricCamera small_rig() {
  return camera::CatadioptricCamera(
      std::make_unique<camera::PinholeCamera>(camera::PinholeIntrinsics{250, 250, 159.5, 119.5}),
      std::make_unique<camera::EquiangularProfile>(5.0, 0.05, 0.02, 0.35),
      camera::MirrorPose{0.01, -0.008, 0.002, -0.001, 0.001}, 320, 240);
}

bool sees_mirror(const camera::CatadioptricCamera& camera, double x, double y) {
  Eigen::Vector3d origin, direction;
  return camera.unproject(Eigen::Vector2d(x, y), &origin, &direction);
}

TEST(ValidRegion, KeepsAMarginFromEveryPixelWithoutAReflection) {
  const auto camera = small_rig();
  constexpr double kMargin = 6;
  const cv::Mat mask = valid_region_mask(camera, kMargin);
  ASSERT_EQ(mask.type(), CV_8UC1);
  ASSERT_EQ(mask.cols, 320);
  ASSERT_EQ(mask.rows, 240);
  // Every pixel's own validity, then its neighbourhood's.
  cv::Mat valid(mask.size(), CV_8UC1);
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) valid.at<uchar>(y, x) = sees_mirror(camera, x, y);
  const int reach = static_cast<int>(kMargin);
  int inside = 0, near_invalid = 0;
  for (int y = 0; y < mask.rows; ++y)
    for (int x = 0; x < mask.cols; ++x) {
      bool all_valid = true;  // every pixel within the margin sees the mirror
      for (int dy = -reach; dy <= reach && all_valid; ++dy)
        for (int dx = -reach; dx <= reach && all_valid; ++dx)
          if (dx * dx + dy * dy <= kMargin * kMargin)
            all_valid = x + dx >= 0 && y + dy >= 0 && x + dx < mask.cols && y + dy < mask.rows &&
                        valid.at<uchar>(y + dy, x + dx);
      if (mask.at<uchar>(y, x)) {
        ++inside;
        EXPECT_TRUE(all_valid) << x << " " << y;
      } else if (all_valid) {
        ++near_invalid;  // allowed only on the margin's edge, where distances round
      }
    }
  EXPECT_GT(inside, 20000);
  EXPECT_LT(near_invalid, 0.05 * inside);
}

TEST(ValidRegion, ExcludesTheCamerasOwnReflectionAndTheSurround) {
  const auto camera = small_rig();
  const cv::Mat mask = valid_region_mask(camera, 3);
  const cv::Point2d centre = region_centre(mask);
  // The region's centre is the image of the axis, where the camera sees itself.
  EXPECT_FALSE(sees_mirror(camera, centre.x, centre.y));
  EXPECT_EQ(mask.at<uchar>(cvRound(centre.y), cvRound(centre.x)), 0);
  EXPECT_EQ(mask.at<uchar>(0, 0), 0);  // beyond the rim
  EXPECT_EQ(mask.at<uchar>(239, 319), 0);
  EXPECT_EQ(mask.at<uchar>(cvRound(centre.y), cvRound(centre.x) + 50), 255);  // the mirror
}

}  // namespace
}  // namespace omnisfm::track
