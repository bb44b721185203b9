#include "omnisfm/sim/photo_texture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "omnisfm/io/shared_data.h"
#include "omnisfm/sim/procedural_texture.h"

namespace omnisfm::sim {
namespace {

// A 64 x 64 photograph of a ramp in x and a ramp in y, 1 m across: texel (i, j) at
// ((i + 0.5) / 64, (j + 0.5) / 64) metres.
cv::Mat ramp_photo() {
  cv::Mat photo(64, 64, CV_8UC1);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) photo.at<std::uint8_t>(j, i) = static_cast<std::uint8_t>(2 * i + j);
  return photo;
}

TEST(PhotoTexture, TexelCentresGiveTheirTexelAndBetweenIsLinear) {
  const PhotoTexture texture(ramp_photo(), 1.0);
  for (int j : {0, 10, 63})
    for (int i : {0, 17, 63})
      EXPECT_NEAR(texture.value({(i + 0.5) / 64, (j + 0.5) / 64}, 0), 2 * i + j, 1e-9);
  // Halfway between texels (3, 5) and (4, 5): the mean.
  EXPECT_NEAR(texture.value({4.0 / 64, 5.5 / 64}, 0), (2 * 3 + 5 + 2 * 4 + 5) / 2.0, 1e-9);
}

TEST(PhotoTexture, RepeatsMirroredWithoutSeams) {
  const PhotoTexture texture(ramp_photo(), 1.0);
  for (double u : {0.013, 0.5, 0.97})
    for (double v : {0.021, 0.61}) {
      // Period 2 m, and mirrored about each edge.
      EXPECT_NEAR(texture.value({u + 2, v - 4}, 0), texture.value({u, v}, 0), 1e-9);
      EXPECT_NEAR(texture.value({-u, v}, 0), texture.value({u, v}, 0), 1e-9);
      EXPECT_NEAR(texture.value({2 - u, v}, 0), texture.value({u, v}, 0), 1e-9);
    }
  // Across the edge at u = 1 the values run on continuously: no seam.
  EXPECT_NEAR(texture.value({1 - 1e-6, 0.3}, 0), texture.value({1 + 1e-6, 0.3}, 0), 1e-3);
}

// An odd size halves unevenly (63 -> 31 -> 15 ...): every level must still repeat where the
// photograph does, 2 m across and 2 * 37 / 63 m down.
TEST(PhotoTexture, OddSizesRepeatInPlaceAtEveryLevel) {
  cv::Mat photo(37, 63, CV_8UC1);
  cv::randu(photo, 0, 256);
  const PhotoTexture texture(photo, 1.0);
  const double down = 2.0 * 37 / 63;
  for (double footprint : {0.0, 3.0 / 63, 7.0 / 63, 20.0 / 63})
    for (const Eigen::Vector2d& uv : {Eigen::Vector2d(0.31, 0.17), Eigen::Vector2d(0.77, 0.52)}) {
      const double here = texture.value(uv, footprint);
      EXPECT_NEAR(texture.value(uv + Eigen::Vector2d(2, 0), footprint), here, 1e-6) << footprint;
      EXPECT_NEAR(texture.value(uv + Eigen::Vector2d(0, down), footprint), here, 1e-6)
          << footprint;
    }
}

TEST(PhotoTexture, WideFootprintsAverageTheTexture) {
  const PhotoTexture texture(ramp_photo(), 1.0);
  // A footprint of the whole photograph: its mean, 2 * 31.5 + 31.5 = 94.5.
  EXPECT_NEAR(texture.value({0.5, 0.5}, 1.0), 94.5, 0.5);
  // Farther than the photograph itself: the coarsest level, still its mean.
  EXPECT_NEAR(texture.value({0.25, 0.75}, 100.0), 94.5, 0.5);
  // A footprint of 4 texels lies between the 4- and 8-texel levels: it blurs but keeps the ramp's
  // slope at the photograph's middle.
  const double step = 1.0 / 64;
  EXPECT_NEAR(texture.value({0.5 + step, 0.5}, 4 * step) - texture.value({0.5, 0.5}, 4 * step),
              2.0, 0.2);
}

TEST(PhotoTexture, BadPhotographsAndFilesAreRefused) {
  EXPECT_THROW(PhotoTexture(cv::Mat(), 1.0), std::invalid_argument);
  EXPECT_THROW(PhotoTexture(cv::Mat(8, 8, CV_8UC3), 1.0), std::invalid_argument);
  EXPECT_THROW(PhotoTexture(ramp_photo(), 0.0), std::invalid_argument);
  const std::string missing =
      (std::filesystem::temp_directory_path() / "omnisfm-no-such-photo.png").string();
  try {
    PhotoTexture::read(missing, 1.0);
    FAIL() << "read a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_THROW(SurfacePhotos::read(std::filesystem::temp_directory_path().string()),
               std::runtime_error);
}

TEST(SurfacePhotos, TheShippedPhotographsCoverTheTexturesTheyStandFor) {
  const auto photos = SurfacePhotos::read(
      std::filesystem::path(io::find_shared_file("textures/brick.png")).parent_path().string());
  for (int texture = 0; texture < kNumSurfaceTextures; ++texture) {
    const bool expected = texture != kStripedWallTexture && texture != kPlainTexture;
    EXPECT_EQ(SurfacePhotos::has_photo(texture), expected) << texture;
    if (!expected) continue;
    // A photograph's texture: grey levels in range, varying across the surface, and different
    // on two surfaces sharing it.
    double low = 255, high = 0, differs = 0;
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector2d uv(0.037 * k, 0.011 * k);
      const double a = photos->value(texture, surface_seed(texture, 0), uv, 0.005);
      const double b = photos->value(texture, surface_seed(texture, 1), uv, 0.005);
      EXPECT_GE(a, 0);
      EXPECT_LE(a, 255);
      low = std::min(low, a);
      high = std::max(high, a);
      differs += std::abs(a - b);
    }
    EXPECT_GT(high - low, 30) << texture;
    EXPECT_GT(differs / 200, 5) << texture;
  }
  EXPECT_THROW(photos->value(kPlainTexture, 0, {0, 0}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
