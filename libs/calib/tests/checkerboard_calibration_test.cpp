// Full calibration from checkerboards, from a starting guess a user would write: the staged solve
// converges, the held parameters are the unobservable ones, and the calibrated projections agree
// with the truth within the reported uncertainty.

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "omnisfm/calib/cross_validation.h"
#include "omnisfm/calib/projection_uncertainty.h"
#include "omnisfm/calib/staged_calibration.h"
#include "synthetic_boards.h"

namespace omnisfm::calib {
namespace {

constexpr double kNoisePx = 0.2;

StagedReport calibrate_boards(unsigned seed, camera::CatadioptricCamera* camera,
                              std::vector<CalibrationView>* views) {
  *views = testing::board_views(testing::true_hyperbolic_rig(), 10, kNoisePx, seed);
  *camera = testing::nominal_hyperbolic_rig();
  StagedSettings settings;
  settings.groups = {"mirror-pose", "intrinsics", "mirror-shape"};
  return calibrate_in_stages(camera, views, settings);
}

TEST(CheckerboardCalibration, ConvergesFromTheNominalGuess) {
  camera::CatadioptricCamera camera = testing::nominal_hyperbolic_rig();
  std::vector<CalibrationView> views;
  const StagedReport report = calibrate_boards(1, &camera, &views);
  ASSERT_EQ(views.size(), 10u);
  ASSERT_TRUE(report.final.converged) << report.final.message;
  // RMS = noise * sqrt(1 - unknowns / residuals): 10 camera + 60 pose unknowns, 840 residuals.
  EXPECT_NEAR(report.final.rms_px, kNoisePx * std::sqrt(1 - 70.0 / 840), 0.015);
  EXPECT_LE(report.final.num_outliers, 2);
  EXPECT_EQ(report.estimated,
            (std::vector<std::string>{"fx", "fy", "cx", "cy", "conic_kappa", "mirror_rx",
                                      "mirror_ry", "mirror_tx", "mirror_ty", "mirror_tz"}));
  ASSERT_EQ(report.held.size(), 2u);
  EXPECT_EQ(report.held[0].name, "conic_z0");
  EXPECT_EQ(report.held[1].name, "conic_c");
  // Early stages: pose, then pose + intrinsics, then the final solve.
  ASSERT_EQ(report.stages.size(), 3u);
  EXPECT_EQ(report.stages[0].name, "mirror-pose");
  EXPECT_EQ(report.stages[1].name, "mirror-pose+intrinsics");
  EXPECT_GT(report.stages[0].rms_px, report.final.rms_px);
}

// The calibrated camera, with the point held fixed relative to the boards (mrcal's way), sends
// each test pixel's point within its reported 2x2 covariance of the true pixel: the squared
// Mahalanobis distances average 2 (chi-square, 2 degrees of freedom) when the covariance is honest.
TEST(CheckerboardCalibration, ProjectionsMatchTheTruthWithinTheReportedUncertainty) {
  const camera::CatadioptricCamera truth = testing::true_hyperbolic_rig();
  const std::vector<Eigen::Vector2d> test_pixels = {{515 + 150, 390}, {515, 390 - 250},
                                                    {515 - 300, 390}, {515 + 100, 390 + 200}};
  constexpr int kSeeds = 20;
  constexpr double kDistance = 0.4;
  double sum_mahalanobis2 = 0;
  int samples = 0;
  for (unsigned seed = 1; seed <= kSeeds; ++seed) {
    camera::CatadioptricCamera camera = truth;
    std::vector<CalibrationView> views;
    const StagedReport report = calibrate_boards(seed, &camera, &views);
    ASSERT_TRUE(report.final.converged) << seed << ": " << report.final.message;
    const std::vector<CalibrationView> true_views =
        testing::board_views(truth, 10, kNoisePx, seed);
    for (const Eigen::Vector2d& pixel : test_pixels) {
      Eigen::Vector3d origin, direction;
      ASSERT_TRUE(truth.unproject(pixel, &origin, &direction));
      const Eigen::Vector3d X_true = origin + kDistance * direction;
      // The same physical point seen through the calibration: via each board's frame.
      Eigen::Vector3d X_estimated = Eigen::Vector3d::Zero();
      for (std::size_t v = 0; v < views.size(); ++v) {
        X_estimated += views[v].cam_from_object * (true_views[v].cam_from_object.inverse() * X_true);
      }
      X_estimated /= static_cast<double>(views.size());
      Eigen::Vector2d projected;
      ASSERT_TRUE(camera.project(X_estimated, &projected));
      Eigen::Matrix2d covariance;
      ASSERT_TRUE(projection_covariance(camera, report.estimated, views,
                                        report.final.joint_covariance, X_estimated, &covariance));
      const Eigen::Vector2d error = projected - pixel;
      sum_mahalanobis2 += error.dot(covariance.ldlt().solve(error));
      ++samples;
    }
  }
  const double mean = sum_mahalanobis2 / samples;
  EXPECT_GT(mean, 2 / (1.5 * 1.5));
  EXPECT_LT(mean, 2 * 1.5 * 1.5);
}

TEST(CheckerboardCalibration, HeldOutViewsMatchTheNoise) {
  const camera::CatadioptricCamera truth = testing::true_hyperbolic_rig();
  std::vector<CalibrationView> all = testing::board_views(truth, 12, kNoisePx, 7);
  ASSERT_EQ(all.size(), 12u);
  const std::vector<int> held_indices = spread_views(12, 2);
  EXPECT_EQ(held_indices, (std::vector<int>{3, 9}));
  std::vector<CalibrationView> kept, held;
  for (int v = 0; v < 12; ++v) {
    const bool is_held = v == held_indices[0] || v == held_indices[1];
    (is_held ? held : kept).push_back(all[v]);
  }
  camera::CatadioptricCamera camera = testing::nominal_hyperbolic_rig();
  StagedSettings settings;
  settings.groups = {"mirror-pose", "intrinsics", "mirror-shape"};
  ASSERT_TRUE(calibrate_in_stages(&camera, &kept, settings).final.converged);
  const HeldOutResult result = evaluate_held_out(camera, held);
  ASSERT_EQ(result.views.size(), 2u);
  EXPECT_EQ(result.views[0], all[3].name);
  EXPECT_EQ(result.num_observations, 84);
  EXPECT_EQ(result.num_unprojectable, 0);
  // Only 6 pose unknowns per view here: close to the noise, a little above for the model's error.
  EXPECT_GT(result.rms_px, 0.8 * kNoisePx);
  EXPECT_LT(result.rms_px, 1.5 * kNoisePx);

  // The mirror-pose-only model (intrinsics held at the guess) predicts held-out views worse.
  camera::CatadioptricCamera rough = testing::nominal_hyperbolic_rig();
  settings.groups = {"mirror-pose"};
  calibrate_in_stages(&rough, &kept, settings);
  EXPECT_GT(evaluate_held_out(rough, held).rms_px, 2 * result.rms_px);
}

TEST(SpreadViews, RejectsHoldingOutEverything) {
  EXPECT_EQ(spread_views(10, 1), (std::vector<int>{5}));
  EXPECT_EQ(spread_views(4, 3), (std::vector<int>{0, 2, 3}));
  EXPECT_THROW(spread_views(4, 4), std::invalid_argument);
  EXPECT_THROW(spread_views(4, 0), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::calib
