// The filter's published pose covariance against its actual errors over the simulated rover's
// seeds, with odometry and gyro (eval::rover_pose_consistency), vision alone, and with the filter
// linearised at the truth. Over seeds 1-10, 1-25 with OMNISFM_TEST_SIZE=full (CTest label `long`).

#include "omnisfm/eval/filter_consistency.h"

#include <gtest/gtest.h>

#include "imperfect_calibration.h"
#include "omnisfm/sim/scenario.h"
#include "test_size.h"

namespace omnisfm::sfm {
namespace {

// The rover's seeds 1-N (the goals are stated over 25).
int rover_seeds() { return small_or_full(10, 25); }

// The mean NEES within (low, high) and at least `min_inside` of the frames inside the 95 % bound
// (the goal: 90 %).
void expect_honest(const char* what, const eval::PoseConsistency& c, double low, double high,
                   double min_inside = 0.90) {
  std::printf("%s, rover seeds 1-%d: mean NEES %.2f, %.1f %% inside the 95 %% bound\n", what,
              rover_seeds(), c.mean_nees, 100 * c.inside);
  EXPECT_GT(c.mean_nees, low) << what;
  EXPECT_LT(c.mean_nees, high) << what;
  EXPECT_GE(c.inside, min_inside) << what;
}

// The simulation's wheel reading 1.5 % long, its scale a state (the default), seeds 1-25: the goal
// is a mean NEES of 4-8 and 90 % of frames inside the 95 % bound. Measured: 4.68 and 96.1 %
// (5.82 and 92.7 % before the wheels' scale was a considered state; then seeds 1-50: 5.59 and
// 92.7 %, a calibrated wheel, seeds 1-25: 4.07 and 96.8 %). Before each new
// point's anchor was a state it was 344 and 20.7 % (a new point hung on the pose through the
// prior's depth); with the update relinearised at the measurements' own iterates, as under the
// random walk, 18.4 and 48.6 %.
TEST(FilterConsistency, RoverPoseNeesWithOdometryAndGyro) {
  const eval::PoseConsistency c = eval::rover_pose_consistency(rover_seeds());
  expect_honest("wheel +1.5 %", c, 4.0, 8.0);
}

// Vision alone, the published pose covariance holds the map's scale
// (OnlineFilter::vision_scale_log_sigma). Measured over seeds 1-25: mean NEES 2.36, 100 % inside
// the 95 % bound, the map 5.6-6.6x at the last frame; without the scale's term, 7.8e5 and 1.2 %.
TEST(FilterConsistency, VisionAloneThePoseCovarianceHoldsTheScale) {
  eval::RoverStudy camera_alone;
  camera_alone.with_sensors = false;
  const eval::PoseConsistency c =
      eval::rover_pose_consistency(rover_seeds(), FilterSettings(), camera_alone);
  expect_honest("the camera alone", c, 1.0, 8.0);
  std::printf("the map's scale at the last frame %.2f-%.2f; along the scale, linearised, NEES "
              "%.2f (as a logarithm %.2f)\n",
              c.smallest_scale, c.largest_scale, c.mean_linearised_scale_nees,
              c.mean_scale_nees);
  // Along the scale the published sigma holds the translation's error, (1 - 1/s) |t|: measured
  // 0.70 (the map 5.6-6.6x), 1 when honest. A sigma twice as large would give 0.17, one half as
  // large 2.8. As a logarithm the error is 1.8 sigmas (3.3): the linearised term holds a map
  // up to 2x small or any larger, not its logarithm.
  EXPECT_GT(c.mean_linearised_scale_nees, 0.3);
  EXPECT_LT(c.mean_linearised_scale_nees, 1.0);
  EXPECT_GT(c.smallest_scale, 0.5);

  // With odometry the scale is the wheels', estimated or not: a wheel 1.5 % long taken as exact
  // (no scale state) is overconfident, and the vision-alone term must not hide it.
  FilterSettings exact_wheel;
  exact_wheel.estimate_wheel_scale = false;
  const eval::PoseConsistency wrong_wheel = eval::rover_pose_consistency(5, exact_wheel);
  std::printf("rover seeds 1-5, a wheel 1.5 %% long taken as exact: mean NEES %.1f\n",
              wrong_wheel.mean_nees);
  EXPECT_GT(wrong_wheel.mean_nees, 20.0);
}

// Linearised once at the constant velocity (FilterSettings::linearise_at_constant_velocity), vision
// alone keeps the map at the depth priors' scale, near the truth's on the rover (its points about
// initial_depth away), where the iterated update grows it to 5.6-6.6 times: measured over seeds
// 1-25 0.85-1.18 at the last frame (1-10: 0.89-1.18), the pose's mean NEES 2.15 with every frame
// inside the 95 % bound, and along the scale the published sigma larger than the error (the
// linearised NEES along it 0.01).
TEST(FilterConsistency, VisionAloneAtTheConstantVelocityTheMapKeepsItsScale) {
  eval::RoverStudy camera_alone;
  camera_alone.with_sensors = false;
  FilterSettings settings;
  settings.linearise_at_constant_velocity = true;
  const eval::PoseConsistency c =
      eval::rover_pose_consistency(rover_seeds(), settings, camera_alone);
  expect_honest("the camera alone at the constant velocity", c, 1.0, 8.0);
  std::printf(
      "the map's scale at the last frame %.2f-%.2f; along the scale, linearised, NEES "
      "%.2f\n",
      c.smallest_scale, c.largest_scale, c.mean_linearised_scale_nees);
  EXPECT_GT(c.smallest_scale, 0.8);
  EXPECT_LT(c.largest_scale, 1.25);
  EXPECT_LT(c.mean_linearised_scale_nees, 1.0);
}

// The filter's camera a calibration of the rover's, off by a draw from that calibration's
// covariance (imperfect_calibration.h), the wheel reading 1.5 % long: with the covariance
// considered (FilterSettings::camera_uncertainty) the goal holds as with the exact camera.
// Measured, seeds 1-25: 5.49 and 93.0 % inside. Taken as exact, the same cameras give 30.2 and
// 30.2 %; on seeds 1-5, checked here so that the test shows what it guards against, 33.0.
TEST(FilterConsistency, RoverPoseNeesWithTheCalibrationsUncertaintyConsidered) {
  sim::SimulationOptions rover;
  rover.scenario = "rover";
  const CameraPrior calibration = lab_target_calibration_prior(sim::simulate(rover).camera);
  FilterSettings settings;
  settings.camera_uncertainty = calibration;
  eval::RoverStudy calibrated;
  calibrated.calibration_error = &calibration;
  const eval::PoseConsistency c = eval::rover_pose_consistency(rover_seeds(), settings, calibrated);
  expect_honest("calibrated camera considered", c, 4.0, 8.0);

  // Without the smoothed start, whose sensitivity otherwise carries most of the first points'
  // dependence on the camera, each new point's ray does (FilterState::add's G_camera): measured
  // 4.77 and 96.3 %, and 9.3 with G_camera left out.
  settings.smoothed_start_frames = 0;
  const eval::PoseConsistency plain =
      eval::rover_pose_consistency(rover_seeds(), settings, calibrated);
  expect_honest("the same without the smoothed start", plain, 3.0, 7.0);

  const eval::PoseConsistency exact = eval::rover_pose_consistency(5, {}, calibrated);
  std::printf("rover seeds 1-5, calibrated camera taken as exact: mean NEES %.2f, %.1f %% inside\n",
              exact.mean_nees, 100 * exact.inside);
  EXPECT_GT(exact.mean_nees, 15.0);
}

// The simulation's wheel reading 1.5 % long, its scale a state, the filter linearised at the
// truth (Huang, Mourikis and Roumeliotis's ideal EKF): its model is honest, which is how the
// linearisations that made the filter overconfident were found (online_filter.h). Measured:
// seeds 1-25 mean 5.37, 95.9 % inside (7.43 and 93.1 % with the depth priors kept).
TEST(FilterConsistency, LinearisedAtTheTruthTheModelIsHonestWithTheWheelsError) {
  FilterSettings settings;
  settings.estimate_wheel_scale = true;
  eval::RoverStudy at_truth;
  at_truth.linearised_at_truth = true;
  const eval::PoseConsistency c = eval::rover_pose_consistency(rover_seeds(), settings, at_truth);
  // Over the small size's 10 seeds, where a seed's frames, which err together, weigh more: 89.4 %
  // inside there (95.9 % over 25), so 85 %; the goals' tests above hold 90 % at every size.
  expect_honest("wheel +1.5 %, at the truth", c, 4.0, 8.0, small_or_full(0.85, 0.90));
}

}  // namespace
}  // namespace omnisfm::sfm
