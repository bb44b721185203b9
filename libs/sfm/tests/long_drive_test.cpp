// The 20,000-frame drive (600 m), the filter alone: with the simulated wheel (reading 1.5 % long)
// and biased gyro within 1 % of the distance after a rigid alignment (the goal is 2 %), vision
// alone within 1 % after a similarity, no good track rejected, and with the sliding window a
// covariance that holds, or linearised at the constant velocity a map at the depth priors' scale;
// and the wheels' scale it finds over 3,000 frames. 5-10 s per seed, 30 with the sliding window, so
// under the CTest label `long`.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/eval/filter_run.h"
#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/gps_receiver.h"
#include "omnisfm/sim/scenario.h"
#include "test_size.h"

namespace omnisfm::sfm {
namespace {

// A drive of `frames` frames and its simulated wheel (reading 1.5 % long) and biased gyro, with
// the simulated RTK receiver's fixes when asked.
struct SensedDrive {
  sim::Dataset drive;
  MotionSensors sensors;
  double wheel_scale_error = 0;
};

SensedDrive sensed_drive(int frames, std::uint64_t seed,
                         const camera::CatadioptricCamera& camera = sim::default_rig(1024, 768),
                         bool with_gps = false) {
  SensedDrive d{sim::long_drive(frames, 0.2, seed, camera), {}, 0};
  sim::DeadReckoningOptions options;
  options.seed = seed;
  const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(d.drive, options);
  sim::GpsOptions receiver;
  receiver.seed = seed;
  const sim::GpsTrack gps = with_gps ? sim::simulate_gps(d.drive, receiver) : sim::GpsTrack();
  d.sensors = eval::motion_sensors(&dead_reckoning, options, with_gps ? &gps : nullptr);
  d.wheel_scale_error = options.odometry_scale_error;
  return d;
}

// The filter alone (no batch) through the fused pipeline.
SfmResult online_run(const sim::Dataset& drive, const MotionSensors& sensors) {
  SfmSettings online;
  online.run_batch = false;
  return run_fused_sfm(drive.camera, drive.observations, drive.timestamps, sensors, online);
}

// The frame whose interval from the previous frame holds time t.
int frame_after(const sim::Dataset& drive, double t) {
  const std::vector<double>& times = drive.timestamps;
  return static_cast<int>(std::upper_bound(times.begin(), times.end(), t) - times.begin());
}

// Through the fused pipeline at seed 3; seeds 1 and 2 are driven by the filter alone below
// (WithTheSensorsThePoseCovarianceStaysNearHonest and ...Elsewhere), with the same checks.
TEST(LongDrive, OdometryAndGyroHoldOnePercentOverSixHundredMetres) {
  constexpr std::uint64_t seed = 3;
  const auto [drive, sensors, wheel_error] = sensed_drive(20000, seed);
  const SfmResult r = online_run(drive, sensors);
  const auto rigid = eval::trajectory_errors(r.online_world_from_cam, drive.world_from_cam, false);
  std::printf("drive seed %d: %.0f m, rigid %.2f %% of the distance, rotation %.2f deg\n",
              static_cast<int>(seed), rigid.distance_travelled_m, rigid.translation_error_percent,
              rigid.mean_rotation_error_deg);
  // Measured at seeds 1-3: 0.46 / 0.15 / 0.23 %, mean rotation errors 2.5 / 0.95 / 1.3
  // deg; 1.76-1.91 % and 11.5-12.6 deg before each point's anchor was a state and the priors were
  // taken back.
  EXPECT_LT(rigid.translation_error_percent, 1.0) << "seed " << seed;
  EXPECT_TRUE(r.outliers.empty()) << r.outliers.size() << " good tracks rejected";
  EXPECT_TRUE(r.refused_motion_frames.empty())
      << r.refused_motion_frames.size() << " good predictions refused";
}

// GPS fixes at odds with the rest are judged by the filter's trajectory, which drifts metres over
// 600 m where the simulated RTK receiver is good to 2 cm: none of the 10,000 good fixes is refused
// (seeds 1-3 measured), and one 50 m off is (at seeds 1-2; 10 m off at seed 2 only, the drift's
// spread hiding it at seed 1).
TEST(LongDrive, GpsFixesAtOddsAreRefusedAndNoGoodOne) {
  auto [drive, sensors, wheel_error] = sensed_drive(20000, 1, sim::default_rig(1024, 768), true);
  const int n = static_cast<int>(sensors.gps.size());
  sensors.gps[n / 2].enu.x() += 50;
  const SfmResult r = online_run(drive, sensors);
  EXPECT_EQ(n, 10000);
  EXPECT_EQ(r.refused_gps_fixes, std::vector<int>{n / 2});
}

// The filter alone over the 20,000-frame drive, fed as run_fused_sfm feeds it: with the simulated
// wheel (reading 1.5 % long) and biased gyro, or vision alone. The mean NEES of its published pose
// over the last 5,000 frames (6 when honest), the drive's error after a rigid alignment and after
// a similarity, the tracks it rejected, the sensors' predictions it refused, and the wheels'
// scale's sigma at the end.
struct DriveRun {
  double late_nees = 0;
  double rigid_percent = 0;
  eval::TrajectoryErrors similar;
  size_t rejected = 0;
  long refused_motions = 0;
  double wheel_scale_sigma = 0;
};

DriveRun drive_run(const FilterSettings& settings, std::uint64_t seed = 1,
                   const camera::CatadioptricCamera& camera = sim::default_rig(1024, 768),
                   bool with_sensors = true) {
  constexpr int kFrames = 20000, kLate = 5000;
  const SensedDrive sensed = sensed_drive(kFrames, seed, camera);
  const sim::Dataset& drive = sensed.drive;  // (a structured binding cannot be captured in C++17)
  OnlineFilter filter(drive.camera, settings);
  const Eigen::Isometry3d first_from_world = drive.world_from_cam[0].inverse();
  std::vector<Eigen::Isometry3d> estimate;
  DriveRun result;
  eval::run_filter(drive, with_sensors ? &sensed.sensors : nullptr, settings, &filter, [&](int f) {
    estimate.push_back(drive.world_from_cam[0] * filter.cam_from_world().inverse());
    if (f >= kFrames - kLate) {
      const Eigen::Isometry3d truth = (first_from_world * drive.world_from_cam[f]).inverse();
      const Eigen::Matrix<double, 6, 1> e = eval::filter_pose_error(truth, filter.cam_from_world());
      result.late_nees += e.dot(filter.pose_covariance().ldlt().solve(e)) / kLate;
    }
  });
  result.rigid_percent =
      eval::trajectory_errors(estimate, drive.world_from_cam, false).translation_error_percent;
  result.similar = eval::trajectory_errors(estimate, drive.world_from_cam, true);
  result.rejected = filter.rejected().size();
  result.refused_motions = filter.refused_motions();
  result.wheel_scale_sigma = std::sqrt(filter.wheel_scale_variance());
  return result;
}

DriveRun vision_alone_drive(std::uint64_t seed, const FilterSettings& settings) {
  const DriveRun d = drive_run(settings, seed, sim::default_rig(1024, 768), false);
  std::printf("vision alone, seed %d, window %d: %.2f %% of the distance after a similarity, "
              "rotation %.2f deg, late NEES %.1f\n",
              static_cast<int>(seed), settings.smoothing_window_frames,
              d.similar.translation_error_percent, d.similar.mean_rotation_error_deg, d.late_nees);
  return d;
}

// Vision alone the scale is the images' through a few centimetres of mirror and the filter's own
// depth priors; after a similarity alignment the goal is 2 % of the distance and 2 deg. Measured
// 0.18 / 0.38 / 0.27 % and 0.86 / 2.07 / 1.99 deg mean orientation error (the orientation drifts,
// its tilt with a sign); 8.1-10.1 % and 34 deg while the state's origin stayed at the first frame.
// A seed per test, so that CTest runs them side by side (seed 2 at the full size only); seed 3's
// drive is the sliding window's test's.
void expect_vision_alone_holds_the_shape(const DriveRun& d) {
  EXPECT_LT(d.similar.translation_error_percent, 1.0);
  EXPECT_LT(d.similar.mean_rotation_error_deg, 2.5);
  EXPECT_EQ(d.rejected, 0u) << "good tracks rejected";
}

class LongDriveVisionAlone : public testing::TestWithParam<std::uint64_t> {};

TEST_P(LongDriveVisionAlone, HoldsTheShapeOverSixHundredMetres) {
  if (GetParam() > 1 && !full_size_checks()) GTEST_SKIP() << "at OMNISFM_TEST_SIZE=full only";
  expect_vision_alone_holds_the_shape(vision_alone_drive(GetParam(), FilterSettings()));
}

INSTANTIATE_TEST_SUITE_P(Seeds, LongDriveVisionAlone, testing::Values(1, 2));

// Told twice the tracks' noise (pixel_sigma 0.4 for the drive's 0.2 px), the filter alone holds
// the orientation within the goal's 2 deg at every one of seeds 1-24: 1.03 / 1.96 / 1.50 deg at
// seeds 1-3, 1.41 on average and 1.98 at most, where the default 0.3 gives 0.86 / 2.07 / 1.99,
// 1.56 and 2.51 (build/bench/drive_nees 20000 S 20000 0.015 1 0 pixel_sigma=0.4). Its published
// covariance is nearer honest too: mean NEES over the last 5,000 frames 5.3 / 96 / 122 at seeds
// 1-3 against 149 / 438 / 567, each bound below the default's (at seed 1 the NEES is what tells
// the setting from the default, whose 0.86 deg also passes). Seeds 2 and 3 at the full size,
// seed 2's 1.96 deg a thin margin on the goal.
class LongDriveVisionAloneToldTwiceTheNoise : public testing::TestWithParam<std::uint64_t> {};

TEST_P(LongDriveVisionAloneToldTwiceTheNoise, HoldsTheOrientationWithinTwoDegrees) {
  const std::uint64_t seed = GetParam();
  if (seed > 1 && !full_size_checks()) GTEST_SKIP() << "at OMNISFM_TEST_SIZE=full only";
  FilterSettings told;
  told.pixel_sigma = 0.4;
  const DriveRun d = vision_alone_drive(seed, told);
  EXPECT_LT(d.similar.translation_error_percent, 1.0);
  EXPECT_LT(d.similar.mean_rotation_error_deg, 2.0);
  EXPECT_EQ(d.rejected, 0u) << "good tracks rejected";
  const double nees_bound = seed == 1 ? 20 : seed == 2 ? 200 : 250;
  EXPECT_LT(d.late_nees, nees_bound);
}

INSTANTIATE_TEST_SUITE_P(Seeds, LongDriveVisionAloneToldTwiceTheNoise, testing::Values(1, 2, 3));

// Linearised once at the constant velocity (FilterSettings::linearise_at_constant_velocity), the
// filter alone keeps the map near the scale the depth priors gave it, here the truth's (the scene's
// points about initial_depth away; at 4 m the map is 1.36 times the truth's at 300 m and 1.20 at
// 600 m), where the iterated update's bias grows it to 3.5 times: 0.95 / 0.93 / 0.95 at seeds 1-3
// by the similarity that aligns the drive to the truth, the distance then 0.61 / 0.45 / 0.55 % off,
// the orientation 1.59 / 1.45 / 1.24 deg (over seeds 1-24 1.55 on average, as the default's, and
// 2.59 at most), no track rejected, the pose's mean NEES over the last 5,000 frames 159 / 30 / 25
// (the default's 149 / 438 / 567), as this test prints them (the distance and orientation also by
// build/bench/drive_nees 20000 S 20000 0.015 1 0 linearise_at_constant_velocity=1). At the full
// size only: at the small one the rover's seeds check the setting
// (FilterConsistency.VisionAloneAtTheConstantVelocityTheMapKeepsItsScale).
class LongDriveVisionAloneAtTheConstantVelocity : public testing::TestWithParam<std::uint64_t> {};

TEST_P(LongDriveVisionAloneAtTheConstantVelocity, KeepsTheMapsScaleNearTheTruths) {
  const std::uint64_t seed = GetParam();
  if (!full_size_checks()) GTEST_SKIP() << "at OMNISFM_TEST_SIZE=full only";
  FilterSettings settings;
  settings.linearise_at_constant_velocity = true;
  const DriveRun d = vision_alone_drive(seed, settings);
  const double map_scale = 1 / d.similar.alignment.scale;
  std::printf("seed %d: the map %.3f times the truth's, %.2f %%, %.2f deg, late NEES %.1f\n",
              static_cast<int>(seed), map_scale, d.similar.translation_error_percent,
              d.similar.mean_rotation_error_deg, d.late_nees);
  EXPECT_GT(map_scale, 0.8);
  EXPECT_LT(map_scale, 1.25);
  EXPECT_LT(d.similar.translation_error_percent, 1.0);
  EXPECT_LT(d.similar.mean_rotation_error_deg, 2.0);
  EXPECT_EQ(d.rejected, 0u) << "good tracks rejected";
}

INSTANTIATE_TEST_SUITE_P(Seeds, LongDriveVisionAloneAtTheConstantVelocity,
                         testing::Values(1, 2, 3));

// With the sliding window (FilterSettings::smoothing_window_frames) the published pose covariance
// does not fall apart with the drive's length as the filter's alone does. Measured at seed 3, the
// mean NEES over the last 5,000 frames: 20.0 with windows of 60 frames, 567 without (seeds 1-2:
// 23 / 12 against 149 / 438); 1.36 % and 2.08 deg after a similarity.
TEST(LongDrive, VisionAloneTheSlidingWindowKeepsTheCovarianceNearHonest) {
  FilterSettings window;
  window.smoothing_window_frames = 60;
  const DriveRun with = vision_alone_drive(3, window);
  const DriveRun without = vision_alone_drive(3, FilterSettings());
  expect_vision_alone_holds_the_shape(without);
  EXPECT_LT(with.late_nees, 40);
  EXPECT_GT(without.late_nees, 200) << "the drive no longer shows the overconfidence";
  EXPECT_LT(with.similar.translation_error_percent, 2.0);
  EXPECT_LT(with.similar.mean_rotation_error_deg, 2.5);
  EXPECT_EQ(with.rejected, 0u);
}

// With odometry and gyro the published pose covariance stays near honest over the drive, by the
// three choices made for it; undoing any one makes it overconfident. Measured over frames
// 15,000-20,000, mean NEES (6 when honest) and the drive's error after a rigid alignment:
// - the default (the state's frame follows the camera's position and orientation, the wheels'
//   scale considered): 4.3, 0.46 %;
// - the frame left at the first frame: 15,488, 0.60 % (the updates' spurious information on
//   the rotation about that far origin);
// - the frame following the camera's position only: 16.7, 0.26 % (less of the same: the
//   orientation's sigma stays at 1.5 deg while its error drifts to 4 deg);
// - the wheels' scale moved by the images: 51, 0.69 % (it follows the images' own scale to
//   0.949 +- 0.0015 for a true 0.985).
TEST(LongDrive, WithTheSensorsThePoseCovarianceStaysNearHonest) {
  const FilterSettings defaults;
  FilterSettings left = defaults, position_only = defaults, scale_estimated = defaults;
  left.origin_follows_camera = OriginFollowsCamera::kVisionAlone;
  position_only.origin_turns_with_camera = OriginTurnsWithCamera::kNever;
  scale_estimated.wheel_scale_from_images = true;
  const DriveRun d = drive_run(defaults);
  const DriveRun l = drive_run(left);
  const DriveRun p = drive_run(position_only);
  const DriveRun e = drive_run(scale_estimated);
  std::printf("frames 15,000-20,000, mean NEES and the drive's rigid error: default %.1f, "
              "%.2f %%; origin left %.1f, %.2f %%; position only %.1f, %.2f %%; wheels' scale "
              "estimated %.1f, %.2f %%\n",
              d.late_nees, d.rigid_percent, l.late_nees, l.rigid_percent, p.late_nees,
              p.rigid_percent, e.late_nees, e.rigid_percent);
  EXPECT_LT(d.late_nees, 12);
  EXPECT_GT(d.late_nees, 2) << "the covariance has grown wider than the errors";
  EXPECT_LT(d.rigid_percent, 1.0);
  EXPECT_EQ(d.rejected, 0u) << "good tracks rejected";
  EXPECT_EQ(d.refused_motions, 0) << "good predictions refused";
  // Considered, the wheels' scale keeps the calibration's sigma; estimated, the images narrow it.
  EXPECT_DOUBLE_EQ(d.wheel_scale_sigma, 0.02);
  EXPECT_LT(e.wheel_scale_sigma, 0.005);
  EXPECT_GT(l.late_nees, 1000) << "the drive no longer shows the far origin's overconfidence";
  EXPECT_GT(p.late_nees, 2 * d.late_nees) << "turning the frame no longer matters";
  EXPECT_GT(e.late_nees, 4 * d.late_nees) << "the images no longer pull the estimated scale";
}

// Not the first seed's and the simulator's rig's alone: seed 2, and seed 2 through the hyperbolic
// rig of share/omnisfm/cameras. Measured over frames 15,000-20,000: mean NEES 4.9 and 4.1, the
// drive 0.15 and 0.09 % off after a rigid alignment.
TEST(LongDrive, WithTheSensorsThePoseCovarianceStaysNearHonestElsewhere) {
  const char* source = std::getenv("OMNISFM_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "ctest sets OMNISFM_SOURCE_DIR";
  const DriveRun seed_two = drive_run(FilterSettings(), 2);
  const DriveRun hyperbolic = drive_run(
      FilterSettings(), 2,
      io::read_camera_file(std::string(source) + "/share/omnisfm/cameras/hyperbolic.ini"));
  std::printf("frames 15,000-20,000, seed 2: mean NEES %.1f, %.2f %%; through the hyperbolic rig "
              "%.1f, %.2f %%\n",
              seed_two.late_nees, seed_two.rigid_percent, hyperbolic.late_nees,
              hyperbolic.rigid_percent);
  for (const DriveRun& d : {seed_two, hyperbolic}) {
    EXPECT_LT(d.late_nees, 12);
    EXPECT_GT(d.late_nees, 2);
    EXPECT_LT(d.rigid_percent, 1.0);
    EXPECT_EQ(d.rejected, 0u) << "good tracks rejected";
    EXPECT_EQ(d.refused_motions, 0) << "good predictions refused";
  }
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
  const auto [drive, sensors, wheel_error] = sensed_drive(3000, 1);
  const double truth = 1 / (1 + wheel_error);
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

// A wheel that stops counting, or a gyro stuck at zero, halfway through 4,000 frames (120 m). On
// the drive each frame after the fault misfits grossly (35-145, the bound 27.6), not by a little as
// on the rover: the filter refuses the sensors frame after frame and takes the random walk, paced
// by the last step the wheels measured, the images holding the second half; where the wheels
// alone are at odds with the frames' estimated motion, with the gyro's rotation. Measured at seeds
// 1-5 through the default and hyperbolic rigs: every frame from the fault's on refused, 0-14 tracks
// rejected, mean rotation error 0.25-1.02 deg; after a rigid alignment 0.12-0.29 % with the wheel
// frozen (0.27-0.52 % without the gyro's rotation), 0.30-0.61 % with the gyro stuck (clean
// 0.05-0.21 %). With the set walk's 5 cm instead of the paced one the scale grew: 19-20 % after a
// rigid alignment, 6.5 % after a similarity. When each gross frame took the constant velocity,
// fed back its own estimates it diverged within 30 frames: at seed 1, with the wheel frozen, 1,998
// good tracks rejected and 29.8 deg. Odometry without a gyro, the wheel frozen: 0.32-0.37 % and
// 0.41-0.65 deg at seeds 1-3 (clean, odometry alone, 0.27-0.38 %), no track rejected; before the
// filter judged such a prediction after the update too, no frame was refused (a tilt stood for
// the missing distance) and the drive collapsed (seed 1: 1,025 good tracks rejected, 69 deg).
// A gyro alone: the translation is the walk's, whose misfit grows with the map
// vision alone, so the prediction is judged by the images' agreement after a trial update. Clean,
// no frame is refused; stuck at 0 or its bias jumping by 0.02 rad/s halfway, every frame from the
// fault's on, no track rejected and the mean rotation error after a similarity 0.49-0.74 deg
// (clean 0.72-1.13) at seeds 1-3. Judged on each point's prediction, the clean gyro was refused
// in 1,312-1,572 frames, and stuck or jumping it cost 8-34 deg and 18-126 good tracks.
TEST(LongDrive, ASensorThatFailsForGoodIsRefusedFromItsFrameOn) {
  constexpr int kFrames = 4000;
  for (int seed = 1; seed <= small_or_full(1, 3); ++seed) {
    const SensedDrive clean = sensed_drive(kFrames, seed);
    std::set<int> tracks;
    for (const auto& o : clean.drive.observations) tracks.insert(o.track);
    MotionSensors frozen = clean.sensors, stuck = clean.sensors;
    const size_t half = frozen.odometry.size() / 2;
    const int wheel_fault = frame_after(clean.drive, frozen.odometry[half - 1].timestamp);
    for (size_t i = half; i < frozen.odometry.size(); ++i)
      frozen.odometry[i].pose = frozen.odometry[half - 1].pose;
    const size_t gyro_half = stuck.gyro.size() / 2;
    const int gyro_fault = frame_after(clean.drive, stuck.gyro[gyro_half].timestamp);
    MotionSensors jumped = clean.sensors;
    for (size_t i = gyro_half; i < stuck.gyro.size(); ++i) {
      stuck.gyro[i].rate.setZero();
      jumped.gyro[i].rate.z() += 0.02;
    }
    MotionSensors frozen_alone = frozen, gyro_alone = clean.sensors, stuck_alone = stuck,
                  jumped_alone = jumped;
    frozen_alone.gyro.clear();
    for (MotionSensors* s : {&gyro_alone, &stuck_alone, &jumped_alone}) s->odometry.clear();
    struct Case {
      const char* what;
      const MotionSensors& sensors;
      int fault_frame;     // -1: clean
      double rigid_limit;  // percent; 0: the images' scale (a gyro alone), not asserted
    };
    for (const Case& c : {Case{"wheel frozen", frozen, wheel_fault, 0.25},
                          Case{"gyro stuck", stuck, gyro_fault, 1.0},
                          Case{"wheel frozen, no gyro", frozen_alone, wheel_fault, 1.0},
                          Case{"gyro alone, clean", gyro_alone, -1, 0},
                          Case{"gyro alone, stuck", stuck_alone, gyro_fault, 0},
                          Case{"gyro alone, bias jumped", jumped_alone, gyro_fault, 0}}) {
      const SfmResult r = online_run(clean.drive, c.sensors);
      const auto errors = eval::trajectory_errors(r.online_world_from_cam,
                                                  clean.drive.world_from_cam, c.rigid_limit == 0);
      std::printf(
          "seed %d, %s: %.2f %% after a %s alignment, rotation %.2f deg, %zu frames refused "
          "from %d, %zu tracks rejected\n",
          seed, c.what, errors.translation_error_percent,
          c.rigid_limit == 0 ? "similarity" : "rigid", errors.mean_rotation_error_deg,
          r.refused_motion_frames.size(),
          r.refused_motion_frames.empty() ? -1 : r.refused_motion_frames.front(),
          r.outliers.size());
      const std::string at = std::string(c.what) + ", seed " + std::to_string(seed);
      EXPECT_LT(r.outliers.size(), 0.01 * tracks.size()) << at;
      EXPECT_LT(errors.mean_rotation_error_deg, 2.0) << at;
      if (c.rigid_limit > 0) {
        EXPECT_LT(errors.translation_error_percent, c.rigid_limit) << at;
      }
      if (c.fault_frame < 0) {
        EXPECT_TRUE(r.refused_motion_frames.empty()) << at;
        continue;
      }
      ASSERT_FALSE(r.refused_motion_frames.empty()) << at;
      EXPECT_GE(r.refused_motion_frames.front(), c.fault_frame - 1) << at;
      EXPECT_GE(r.refused_motion_frames.size(), 0.99 * (kFrames - c.fault_frame)) << at;
    }
  }
}

// A lone sensor's prediction is judged by a trial update, whose scores follow the tracks' own
// noise; at 0.4 px, beyond the 0.3 px stated but short of where the filter takes the noise
// (twice the variance), neither the gyro alone nor the wheels alone is refused in any frame
// (seeds 1-2; 0.3 px too). Held to chi-square's quartile at the stated noise instead, each was
// refused in 3,993-3,997 of the 4,000 frames at 0.3 and 0.4 px, and with that quartile's margin
// (4) in 479-932 at 0.4 px.
TEST(LongDrive, ALoneSensorIsNotRefusedForTheTracksNoise) {
  constexpr std::uint64_t seed = 1;
  const sim::Dataset drive = sim::long_drive(4000, 0.4, seed, sim::default_rig(1024, 768));
  sim::DeadReckoningOptions options;
  options.seed = seed;
  const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(drive, options);
  const MotionSensors both = eval::motion_sensors(&dead_reckoning, options, nullptr);
  MotionSensors gyro = both, wheels = both;
  gyro.odometry.clear();
  wheels.gyro.clear();
  for (const auto& [what, sensors] : {std::pair{"gyro alone", gyro}, {"wheels alone", wheels}}) {
    const SfmResult r = online_run(drive, sensors);
    std::printf("%s at 0.4 px: %zu frames refused, %zu tracks rejected\n", what,
                r.refused_motion_frames.size(), r.outliers.size());
    EXPECT_TRUE(r.refused_motion_frames.empty()) << what;
  }
}

// A lone sensor over the 600 m drive: the state's frame, as it moves, keeps its axes unless the
// sensors measured the whole motion (FilterSettings::origin_turns_with_camera). Measured at seeds
// 1-2, mean rotation error after a similarity: a gyro alone 1.76 / 2.24 deg, the wheels alone
// 1.97 / 1.06 deg; where the frame turned with every sensor-predicted frame, 7.32 / 8.62 and
// 9.83 / 9.27 deg.
TEST(LongDrive, ALoneSensorKeepsTheOrientationOverSixHundredMetres) {
  const SensedDrive d = sensed_drive(20000, 1);
  MotionSensors gyro = d.sensors, wheels = d.sensors;
  gyro.odometry.clear();
  wheels.gyro.clear();
  for (const auto& [what, sensors] : {std::pair{"gyro alone", gyro}, {"wheels alone", wheels}}) {
    const SfmResult r = online_run(d.drive, sensors);
    const auto similarity =
        eval::trajectory_errors(r.online_world_from_cam, d.drive.world_from_cam, true);
    std::printf("%s over 600 m: %.2f %% after a similarity, rotation %.2f deg, %zu refused\n", what,
                similarity.translation_error_percent, similarity.mean_rotation_error_deg,
                r.refused_motion_frames.size());
    EXPECT_LT(similarity.mean_rotation_error_deg, 3.0) << what;
    EXPECT_LT(similarity.translation_error_percent, 2.0) << what;
  }
}

}  // namespace
}  // namespace omnisfm::sfm
