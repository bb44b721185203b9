#include "omnisfm/track/patch_alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "synthetic_images.h"

namespace omnisfm::track {
namespace {

using testing::WaveTexture;

cv::Mat as_float(const cv::Mat& image) {
  cv::Mat f;
  image.convertTo(f, CV_32F);
  return f;
}

// The image point where the texture point shown at `reference_pixel` of the reference image
// (identity texture mapping) appears in an image with texture_from_image = (A, b).
Eigen::Vector2d moved(const Eigen::Matrix2d& A, const Eigen::Vector2d& b,
                      const Eigen::Vector2d& reference_pixel) {
  return A.inverse() * (reference_pixel - b);
}

// Bilinear sampling of the image biases the alignment by up to a few hundredths of a pixel on
// this texture's shortest (6-pixel) waves: the tolerance.
constexpr double kPositionTolerancePx = 0.03;
constexpr double kShapeTolerance = 0.02;

TEST(PatchAlignment, FindsAnAffineMotionToAFewHundredthsOfAPixel) {
  const WaveTexture texture(7);
  const cv::Mat reference =
      as_float(texture.image(160, 160, Eigen::Matrix2d::Identity(), {0, 0}, false));
  const Eigen::Vector2d centre(80, 80);
  ReferencePatch patch;
  ASSERT_TRUE(ReferencePatch::extract(reference, centre, 7, &patch));

  int cases = 0;
  for (const double angle : {0.0, 0.1, -0.3})
    for (const double scale : {1.0, 0.9, 1.12})
      for (const Eigen::Vector2d& shift :
           {Eigen::Vector2d(0.3, -0.45), Eigen::Vector2d(-1.7, 2.2)}) {
        const Eigen::Matrix2d A = Eigen::Rotation2Dd(angle).toRotationMatrix() *
                                  Eigen::Vector2d(scale, 1 / scale * 1.05).asDiagonal();
        const Eigen::Vector2d b = centre - A * (centre + shift);
        const cv::Mat image = as_float(texture.image(160, 160, A, b, false));
        const Eigen::Vector2d truth = moved(A, b, centre);

        // Start from the right affine part and a rough position, as the tracker does.
        AffineWarp warp;
        warp.A = A.inverse();
        warp.b = truth + Eigen::Vector2d(0.8, -0.6);
        const AlignmentResult result = patch.align(image, &warp, 30, 1e-4);
        ASSERT_TRUE(result.converged) << angle << " " << scale;
        EXPECT_LT((warp.b - truth).norm(), kPositionTolerancePx)
            << angle << " " << scale << " " << shift.transpose();
        EXPECT_GT(result.ncc, 0.999);
        // From the identity, the shape is found as well.
        AffineWarp from_identity;
        from_identity.b = truth + Eigen::Vector2d(0.5, 0.5);
        if (patch.align(image, &from_identity, 50, 1e-4).converged) {
          EXPECT_LT((from_identity.b - truth).norm(), kPositionTolerancePx);
          EXPECT_LT((from_identity.A - A.inverse()).norm(), kShapeTolerance);
        }
        ++cases;
      }
  EXPECT_EQ(cases, 18);
}

TEST(PatchAlignment, IgnoresContrastAndBrightness) {
  const WaveTexture texture(3);
  const cv::Mat reference = as_float(texture.image(100, 100, Eigen::Matrix2d::Identity(), {0, 0}));
  ReferencePatch patch;
  ASSERT_TRUE(ReferencePatch::extract(reference, {50, 50}, 7, &patch));
  const cv::Mat shifted =
      as_float(texture.image(100, 100, Eigen::Matrix2d::Identity(), {0.4, -0.3}));
  const cv::Mat dimmer = shifted * 0.6 + 30;
  AffineWarp warp;
  warp.b = {50, 50};
  ASSERT_TRUE(patch.align(dimmer, &warp, 30, 1e-4).converged);
  EXPECT_LT((warp.b - Eigen::Vector2d(49.6, 50.3)).norm(), kPositionTolerancePx);
}

TEST(PatchAlignment, RefusesFlatPatchesAndPatchesOutsideTheImage) {
  const cv::Mat flat(60, 60, CV_32FC1, cv::Scalar(100));
  ReferencePatch patch;
  EXPECT_FALSE(ReferencePatch::extract(flat, {30, 30}, 7, &patch));
  const cv::Mat textured =
      as_float(WaveTexture(1).image(60, 60, Eigen::Matrix2d::Identity(), {0, 0}));
  EXPECT_FALSE(ReferencePatch::extract(textured, {5, 30}, 7, &patch));
  ASSERT_TRUE(ReferencePatch::extract(textured, {30, 30}, 7, &patch));
  AffineWarp warp;
  warp.b = {55, 30};
  EXPECT_FALSE(patch.align(textured, &warp, 10, 1e-3).converged);
  EXPECT_EQ(patch.ncc(textured, warp), -1);
}

TEST(PatchAlignment, CorrelationTellsADifferentPatchApart) {
  const WaveTexture texture(11);
  const cv::Mat image = as_float(texture.image(200, 200, Eigen::Matrix2d::Identity(), {0, 0}));
  ReferencePatch patch;
  ASSERT_TRUE(ReferencePatch::extract(image, {60, 60}, 7, &patch));
  AffineWarp same, elsewhere;
  same.b = {60, 60};
  elsewhere.b = {140, 120};
  EXPECT_GT(patch.ncc(image, same), 0.9999);
  EXPECT_LT(patch.ncc(image, elsewhere), 0.8);
}

}  // namespace
}  // namespace omnisfm::track
