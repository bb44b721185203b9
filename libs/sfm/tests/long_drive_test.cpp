// The 20,000-frame drive (600 m), the filter alone: with the simulated wheel (reading 1.5 % long)
// and biased gyro within 1 % of the distance after a rigid alignment (the goal is 2 %), vision
// alone within 1 % after a similarity, no good track rejected; and the wheels' scale it finds
// over 3,000 frames. 5-10 s per seed, so under the CTest label `long`.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/eval/filter_run.h"
#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/endless_drive.h"

namespace omnisfm::sfm {
namespace {

TEST(LongDrive, OdometryAndGyroHoldOnePercentOverSixHundredMetres) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const sim::Dataset drive = sim::long_drive(20000, 0.2, seed);
    sim::DeadReckoningOptions options;
    options.seed = seed;
    const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(drive, options);
    const MotionSensors sensors = eval::motion_sensors(&dead_reckoning, options, nullptr);
    SfmSettings online;
    online.run_batch = false;
    const SfmResult r =
        run_fused_sfm(drive.camera, drive.observations, drive.timestamps, sensors, online);
    const auto rigid =
        eval::trajectory_errors(r.online_world_from_cam, drive.world_from_cam, false);
    std::printf("drive seed %d: %.0f m, rigid %.2f %% of the distance, rotation %.2f deg\n",
                static_cast<int>(seed), rigid.distance_travelled_m,
                rigid.translation_error_percent, rigid.mean_rotation_error_deg);
    // Measured 0.52 / 0.50 / 0.28 %, mean rotation errors 2.4 / 1.3 / 1.8 deg; 1.76-1.91 % and
    // 11.5-12.6 deg before each point's anchor was a state and the priors were taken back.
    EXPECT_LT(rigid.translation_error_percent, 1.0) << "seed " << seed;
    EXPECT_TRUE(r.outliers.empty()) << r.outliers.size() << " good tracks rejected";
  }
}

// Vision alone the scale is the images' through a few centimetres of mirror and the filter's own
// depth priors; after a similarity alignment the goal is 2 % of the distance and 2 deg. Measured
// 0.18 / 0.38 / 0.27 % and 0.86 / 2.07 / 1.99 deg mean orientation error (the orientation a random
// walk over 600 m); 8.1-10.1 % and 34 deg while the state's origin stayed at the first frame.
TEST(LongDrive, VisionAloneHoldsTheShapeOverSixHundredMetres) {
  for (std::uint64_t seed : {1, 2, 3}) {
    const sim::Dataset drive = sim::long_drive(20000, 0.2, seed);
    SfmSettings online;
    online.run_batch = false;
    const SfmResult r = run_sfm(drive.camera, drive.observations, online);
    const auto similar =
        eval::trajectory_errors(r.online_world_from_cam, drive.world_from_cam, true);
    std::printf("vision alone, seed %d: %.0f m, %.2f %% of the distance after a similarity, "
                "rotation %.2f deg\n",
                static_cast<int>(seed), similar.distance_travelled_m,
                similar.translation_error_percent, similar.mean_rotation_error_deg);
    EXPECT_LT(similar.translation_error_percent, 1.0) << "seed " << seed;
    EXPECT_LT(similar.mean_rotation_error_deg, 2.5) << "seed " << seed;
    EXPECT_TRUE(r.outliers.empty()) << r.outliers.size() << " good tracks rejected";
  }
}

// The mean NEES of the filter's published pose over the last 5,000 frames of the drive with the
// simulated wheel and gyro (seed 1), and the drive's error after a rigid alignment, fed as
// run_fused_sfm feeds it.
struct DriveConsistency {
  double late_nees = 0;
  double rigid_percent = 0;
};

DriveConsistency drive_consistency(const FilterSettings& settings) {
  constexpr int kFrames = 20000, kLate = 5000;
  const std::uint64_t seed = 1;
  const sim::Dataset drive = sim::long_drive(kFrames, 0.2, seed);
  sim::DeadReckoningOptions options;
  options.seed = seed;
  const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(drive, options);
  const MotionSensors sensors = eval::motion_sensors(&dead_reckoning, options, nullptr);
  OnlineFilter filter(drive.camera, settings);
  const Eigen::Isometry3d first_from_world = drive.world_from_cam[0].inverse();
  std::vector<Eigen::Isometry3d> estimate;
  DriveConsistency result;
  eval::run_filter(drive, &sensors, settings, &filter, [&](int f) {
    estimate.push_back(drive.world_from_cam[0] * filter.cam_from_world().inverse());
    if (f >= kFrames - kLate) {
      const Eigen::Isometry3d truth = (first_from_world * drive.world_from_cam[f]).inverse();
      const Eigen::Matrix<double, 6, 1> e = eval::filter_pose_error(truth, filter.cam_from_world());
      result.late_nees += e.dot(filter.pose_covariance().ldlt().solve(e)) / kLate;
    }
  });
  result.rigid_percent =
      eval::trajectory_errors(estimate, drive.world_from_cam, false).translation_error_percent;
  return result;
}

// With odometry and gyro, the state's origin left at the first frame makes the published
// covariance grow overconfident with the distance (the updates' spurious information on the
// rotation about that origin); following the camera (the default) it stays within a few times
// honest. Measured over frames 15,000-20,000: mean NEES 15,488 with the origin left, 17.0
// following the camera (6 when honest), the drive 0.60 and 0.26 % off after a rigid alignment.
TEST(LongDrive, OriginFollowingTheCameraKeepsThePoseCovarianceNearHonest) {
  FilterSettings settings;
  const DriveConsistency following = drive_consistency(settings);
  settings.origin_follows_camera = OriginFollowsCamera::kVisionAlone;
  const DriveConsistency left = drive_consistency(settings);
  std::printf("frames 15,000-20,000: mean NEES %.1f with the origin left, %.1f following the "
              "camera; %.2f and %.2f %% after a rigid alignment\n",
              left.late_nees, following.late_nees, left.rigid_percent, following.rigid_percent);
  EXPECT_LT(following.late_nees, 40);
  EXPECT_GT(left.late_nees, 1000) << "the drive no longer shows the overconfidence";
  EXPECT_LT(following.rigid_percent, 0.5);
}

// The wheels' scale moved by the images follows their own scale, which drifts, and the filter
// trusts it: measured over frames 15,000-20,000, mean NEES 77 and the drive 0.59 % off after a
// rigid alignment (wheels' scale 0.950 +- 0.0015 for a true 0.985); considered (the default),
// 17.0 and 0.26 %, its sigma the calibration's 2 %.
TEST(LongDrive, WheelScaleConsideredKeepsTheDriveHonest) {
  FilterSettings settings;
  const DriveConsistency considered = drive_consistency(settings);
  settings.wheel_scale_from_images = true;
  const DriveConsistency estimated = drive_consistency(settings);
  std::printf("frames 15,000-20,000: mean NEES %.1f with the wheels' scale considered, %.1f "
              "estimated; %.2f and %.2f %% after a rigid alignment\n",
              considered.late_nees, estimated.late_nees, considered.rigid_percent,
              estimated.rigid_percent);
  EXPECT_LT(considered.late_nees, 40);
  EXPECT_GT(estimated.late_nees, 2 * considered.late_nees)
      << "the images no longer pull the estimated scale";
  EXPECT_LT(considered.rigid_percent, estimated.rigid_percent);
}

// Each new point's depth prior is a guess of the scene's scale; kept, thousands of them pull the
// wheels' scale, where the images move it (FilterSettings::wheel_scale_from_images), with a sigma
// that says it is known. Measured over 3,000 frames (90 m, seed 1):
// 1.0066 +- 0.0009 with the priors kept, 0.9936 +- 0.0009 taken back, for a true 1 / 1.015 =
// 0.9852. What remains is the images' own scale, not the wheel's: over 600 m the estimate is
// 0.993-0.995 at seed 1 whether the wheel reads 3 % long, true or 3 % short (docs/shape-from-
// motion.md, "Endless sequences"), so the bound on the truth holds at the simulation's wheel
// error only.
TEST(LongDrive, TakingBackDepthPriorsRemovesTheirPullOnTheScale) {
  const std::uint64_t seed = 1;
  const sim::Dataset drive = sim::long_drive(3000, 0.2, seed);
  sim::DeadReckoningOptions options;
  options.seed = seed;
  const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(drive, options);
  const MotionSensors sensors = eval::motion_sensors(&dead_reckoning, options, nullptr);
  const double truth = 1 / (1 + options.odometry_scale_error);
  double scale[2] = {0, 0};  // by take_back
  for (bool take_back : {true, false}) {
    SfmSettings settings;
    settings.run_batch = false;
    settings.filter.take_back_depth_priors = take_back;
    settings.filter.wheel_scale_from_images = true;
    const SfmResult r =
        run_fused_sfm(drive.camera, drive.observations, drive.timestamps, sensors, settings);
    const double error = r.online_wheel_scale - truth;
    std::printf("priors %s: wheel scale %.4f +- %.4f, truth %.4f\n",
                take_back ? "taken back" : "kept", r.online_wheel_scale,
                r.online_wheel_scale_sigma, truth);
    if (take_back)
      EXPECT_LT(std::abs(error), 0.013);
    else
      EXPECT_GT(std::abs(error), 0.013) << "the check cannot tell the two apart";
    scale[take_back] = r.online_wheel_scale;
  }
  EXPECT_GT(scale[false] - scale[true], 0.01) << "the 2 m priors no longer pull the scale up";
}

}  // namespace
}  // namespace omnisfm::sfm
