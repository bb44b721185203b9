#include "omnisfm/sim/imaging.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "omnisfm/sim/scenario.h"

namespace omnisfm::sim {
namespace {

Dataset small_rover() {
  SimulationOptions options;
  options.scenario = "rover";
  options.image_width = 160;
  options.image_height = 120;
  return simulate(options);
}

TEST(Imaging, CleanIsTheRenderersImage) {
  const Dataset d = small_rover();
  Renderer renderer(d.camera, 1);
  Imaging camera(ImagingSettings::clean(), &renderer, 1);
  EXPECT_TRUE(ImagingSettings::clean().is_clean());
  EXPECT_FALSE(ImagingSettings().is_clean());
  // A realistic Imaging taking its turn on the same renderer leaves the clean one's images
  // procedural.
  const cv::Mat procedural = renderer.render(d.scene, d.world_from_cam[7]);
  Imaging realistic(ImagingSettings(), &renderer, 1);
  realistic.record(d, 0);
  EXPECT_EQ(cv::norm(camera.record(d, 7), procedural, cv::NORM_INF), 0);
  // The radiance, rounded, is the image (a rounding tie may land either way).
  const cv::Mat radiance = renderer.render_radiance(d.scene, d.world_from_cam[3]);
  cv::Mat rounded;
  radiance.convertTo(rounded, CV_8U);
  EXPECT_LE(cv::norm(rounded, renderer.render(d.scene, d.world_from_cam[3]), cv::NORM_INF), 1);
}

TEST(Imaging, RealisticIsRepeatableForItsSeedAndExposedToMidGrey) {
  const Dataset d = small_rover();
  Renderer renderer(d.camera, 1);
  const cv::Mat valid = renderer.valid_pixels();
  Imaging a(ImagingSettings(), &renderer, 5), b(ImagingSettings(), &renderer, 5),
      c(ImagingSettings(), &renderer, 6);
  for (int frame = 0; frame < 12; ++frame) {
    const cv::Mat image = a.record(d, frame);
    EXPECT_EQ(cv::norm(image, b.record(d, frame), cv::NORM_INF), 0) << frame;
    EXPECT_GT(cv::norm(image, c.record(d, frame), cv::NORM_L1), 0) << frame;
    if (frame == 0) {
      EXPECT_NEAR(cv::mean(image, valid)[0], 115, 3);
    }
  }
  // The automatic exposure's walk stays within 12 % of where it started, and moves.
  Imaging walk(ImagingSettings(), &renderer, 5);
  walk.record(d, 0);
  const double start = walk.gain();
  double low = start, high = start;
  int steps = 0;
  double sum_log_steps_squared = 0, previous = start;
  for (int frame = 1; frame < 120; ++frame) {
    walk.record(d, frame % 12);
    low = std::min(low, walk.gain());
    high = std::max(high, walk.gain());
    // Steps that the bounds did not stop: the walk's own spread.
    if (std::abs(walk.gain() / start - 1) < 0.11 && std::abs(previous / start - 1) < 0.11) {
      sum_log_steps_squared += std::pow(std::log(walk.gain() / previous), 2);
      ++steps;
    }
    previous = walk.gain();
  }
  // The walk reaches its bounds (120 steps of 4 % wander about 44 %) and stays within them.
  EXPECT_GE(low, 0.88 * start - 1e-12);
  EXPECT_LE(high, 1.12 * start + 1e-12);
  EXPECT_GT(high - low, 0.2 * start);
  ASSERT_GT(steps, 30);
  EXPECT_NEAR(std::sqrt(sum_log_steps_squared / steps), 0.04, 0.012);
}

TEST(Imaging, SensorNoiseHasTheStatedSpread) {
  const Dataset d = small_rover();
  Renderer renderer(d.camera, 1);
  // Noise alone, no exposure walk, no blur: image - exposure * radiance is the noise.
  ImagingSettings settings = ImagingSettings::clean();
  settings.electrons_per_grey = 16;
  settings.read_noise_grey = 1.0;
  Imaging camera(settings, &renderer, 3);
  const cv::Mat radiance = renderer.render_radiance(d.scene, d.world_from_cam[0]);
  const cv::Mat image = camera.record(d, 0);
  const double exposure = camera.gain();
  const cv::Mat valid = renderer.valid_pixels();
  double sum_z2 = 0;
  int n = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double g = exposure * radiance.at<float>(y, x);
      if (!valid.at<std::uint8_t>(y, x) || g < 20 || g > 235) continue;
      const double variance = g / 16 + 1 + 1.0 / 12;  // shot, read, quantisation
      sum_z2 += std::pow(image.at<std::uint8_t>(y, x) - g, 2) / variance;
      ++n;
    }
  ASSERT_GT(n, 2000);
  // chi-square per pixel: 1 within the sampling error of n pixels (5 sigma).
  EXPECT_NEAR(sum_z2 / n, 1.0, 5 * std::sqrt(2.0 / n));
}

TEST(Imaging, NamesOtherThanCleanAndRealisticAreRefused) {
  EXPECT_TRUE(ImagingSettings::named("clean").is_clean());
  EXPECT_FALSE(ImagingSettings::named("realistic").is_clean());
  EXPECT_THROW(ImagingSettings::named("Realistic"), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
