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

// The lab's U: at its corners the exposure's poses, averaged as motion blur averages them, are
// centred on the frame's pose (within the parabola's bend, 1.3 mm at 10 cm a frame), where
// straight legs put them 8 mm off; along a leg they are the straight line's.
TEST(Imaging, ExposuresAreCentredOnTheFramesPoseAtACorner) {
  SimulationOptions options;
  options.scenario = "lab";
  const Dataset d = simulate(options);
  ASSERT_GT(d.world_from_cam.size(), 31u);
  const auto mean_position = [&](int frame) {
    // Three renderings over half the interval, as ImagingSettings' defaults take them.
    const double interval = d.timestamps[frame + 1] - d.timestamps[frame];
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const double s : {-1.0 / 6, 0.0, 1.0 / 6})
      sum += pose_during_exposure(d, frame, d.timestamps[frame] + s * interval).translation();
    return Eigen::Vector3d(sum / 3);
  };
  for (const int corner : {10, 30}) {
    const Eigen::Vector3d before =
        d.world_from_cam[corner].translation() - d.world_from_cam[corner - 1].translation();
    const Eigen::Vector3d after =
        d.world_from_cam[corner + 1].translation() - d.world_from_cam[corner].translation();
    ASSERT_LT(std::abs(before.normalized().dot(after.normalized())), 1e-9) << "not a corner";
    // Measured 1.34 mm (0.94 along each leg).
    EXPECT_LT((mean_position(corner) - d.world_from_cam[corner].translation()).norm(), 1.5e-3)
        << corner;
  }
  const double t = d.timestamps[5] + 0.2 * (d.timestamps[6] - d.timestamps[5]);
  const Eigen::Isometry3d on_leg = pose_during_exposure(d, 5, t);
  const Eigen::Vector3d straight =
      0.8 * d.world_from_cam[5].translation() + 0.2 * d.world_from_cam[6].translation();
  EXPECT_LT((on_leg.translation() - straight).norm(), 1e-12);
  EXPECT_LT((on_leg.linear() - d.world_from_cam[5].linear()).norm(), 1e-12);
}

// On the rover's curve the exposure turns with the rig: halfway to the next frame, the pose is
// within a fraction of the step of the straight interpolation, and its rotation the slerp's.
TEST(Imaging, ExposuresFollowTheRigsTurn) {
  const Dataset d = small_rover();
  const int k = 40;
  const double t0 = d.timestamps[k], t1 = d.timestamps[k + 1];
  const Eigen::Isometry3d half = pose_during_exposure(d, k, 0.5 * (t0 + t1));
  const Eigen::Vector3d chord_middle =
      0.5 * (d.world_from_cam[k].translation() + d.world_from_cam[k + 1].translation());
  const double step =
      (d.world_from_cam[k + 1].translation() - d.world_from_cam[k].translation()).norm();
  EXPECT_LT((half.translation() - chord_middle).norm(), 0.05 * step);
  // The rotation halfway is the slerp's, up to the parabola's bend (a small share of the turn).
  const Eigen::Quaterniond from(d.world_from_cam[k].linear()), to(d.world_from_cam[k + 1].linear());
  const double turn = from.angularDistance(to);
  ASSERT_GT(turn, 1e-4) << "the rig does not turn there";
  EXPECT_LT(Eigen::Quaterniond(half.linear()).angularDistance(from.slerp(0.5, to)), 0.05 * turn);
}

TEST(Imaging, NamesOtherThanCleanAndRealisticAreRefused) {
  EXPECT_TRUE(ImagingSettings::named("clean").is_clean());
  EXPECT_FALSE(ImagingSettings::named("realistic").is_clean());
  EXPECT_THROW(ImagingSettings::named("Realistic"), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
