// Sensor readings at odds with the images, through MRPT's objects: a rover rawlog with an
// odometry that jumps, a GPS fix off by multipath and a gyro reading dated far ahead, fed to the
// MRPT estimator and read as `omnisfm run` reads a rawlog (sfm::OnlineFilter::on_motion_refused,
// SfmResult::refused_gps_fixes, MotionSensorCollector). Whole rover runs: not in the sanitizers'
// build.

#include <gtest/gtest.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <cmath>
#include <cstdio>

#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/mrpt_plugin/simulated_rawlog.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The simulated rover's rawlog (seed 1), with its GPS receiver or without; written once.
std::string rover_rawlog(bool with_gps) {
  const std::string path =
      testing::temporary_path(with_gps ? "glitch_rover_gps.rawlog" : "glitch_rover.rawlog");
  static bool written[2] = {false, false};
  if (!written[with_gps]) {
    sim::SimulationOptions simulation;
    simulation.scenario = "rover";
    SimulatedRawlogOptions options;
    if (with_gps) options.gps = sim::GpsOptions();
    write_simulated_rawlog(sim::simulate(simulation), path, options);
    written[with_gps] = true;
  }
  return path;
}

Eigen::Isometry3d isometry(const mrpt::poses::CPose3D& pose) {
  return Eigen::Isometry3d(pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen());
}

// An odometry that jumps 100 m halfway and a gyro reading dated 1,000 s ahead: the estimator's
// last pose stays that of the clean rawlog's (measured under 1 mm apart, the run 3.45 m long),
// where the jump moved it by 99.9 m before the filter judged the sensors' motion.
TEST(OmniSfmEstimator, OutlastsAnOdometryJumpAndAMisdatedGyroReading) {
  std::vector<mrpt::obs::CObservation::Ptr> observations;
  {
    RawlogReader reader(rover_rawlog(false));
    while (const auto object = reader.next())
      observations.push_back(std::dynamic_pointer_cast<mrpt::obs::CObservation>(object));
  }
  std::vector<mrpt::obs::CObservation::Ptr> glitched;
  const std::size_t half = observations.size() / 2;
  bool misdated = false;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const auto& observation = observations[i];
    if (const auto odometry =
            std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(observation);
        odometry && i >= half) {
      auto jumped = std::make_shared<mrpt::obs::CObservationOdometry>(*odometry);
      jumped->odometry.x(jumped->odometry.x() + 100);
      glitched.push_back(jumped);
      continue;
    }
    glitched.push_back(observation);
    if (const auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(observation);
        imu && i >= half / 2 && !misdated) {
      auto ahead = std::make_shared<mrpt::obs::CObservationIMU>(*imu);
      ahead->timestamp = mrpt::Clock::fromDouble(mrpt::Clock::toDouble(imu->timestamp) + 1000);
      ahead->set(mrpt::obs::IMU_WZ, 1.0);
      glitched.push_back(ahead);
      misdated = true;
    }
  }
  ASSERT_TRUE(misdated);
  const auto last_pose = [](const std::vector<mrpt::obs::CObservation::Ptr>& stream) {
    OmniSfmEstimator estimator;
    for (const auto& observation : stream) estimator.processObservation(observation);
    mrpt::poses::CPose3DPDFGaussian pose;
    estimator.getCurrentPoseEstimation(pose);
    return isometry(pose.mean);
  };
  const Eigen::Isometry3d clean = last_pose(observations);
  const Eigen::Isometry3d outlasted = last_pose(glitched);
  const double apart = (clean.translation() - outlasted.translation()).norm();
  std::printf("the last poses %.3f m apart, the run %.2f m from its start\n", apart,
              clean.translation().norm());
  EXPECT_LT(apart, 0.05 * clean.translation().norm());
  EXPECT_LT(Eigen::AngleAxisd(clean.linear().transpose() * outlasted.linear()).angle(), 0.01);
}

// The outdoor rover's rawlog with an odometry that jumps 100 m halfway, a GPS fix 50 m east and a
// gyro reading dated 1,000 s ahead, read as `omnisfm run` reads it: the misdated reading gives way,
// the jump's frame and the fix are refused, and the batch is where the clean rawlog's is (measured
// 0.4 mm apart on average, where without the checks the fix alone moved the rover 1.09 m).
TEST(OutdoorRawlog, GlitchesInTheRawlogAreRefusedAndNamed) {
  const std::string clean_path = rover_rawlog(true);
  std::vector<mrpt::serialization::CSerializable::Ptr> objects;
  {
    RawlogReader reader(clean_path);
    while (auto object = reader.next()) objects.push_back(object);
  }
  std::size_t odometry = 0, fixes = 0, gyro = 0;
  for (const auto& o : objects) {
    odometry += std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o) != nullptr;
    fixes += std::dynamic_pointer_cast<mrpt::obs::CObservationGPS>(o) != nullptr;
    gyro += std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o) != nullptr;
  }
  ASSERT_GT(odometry, 10u);
  ASSERT_GT(fixes, 10u);
  ASSERT_GT(gyro, 10u);
  std::vector<mrpt::serialization::CSerializable::Ptr> glitched;
  std::size_t odometry_seen = 0, fixes_seen = 0, gyro_seen = 0;
  for (const auto& o : objects) {
    if (auto reading = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
      if (odometry_seen++ >= odometry / 2) {
        auto jumped = std::make_shared<mrpt::obs::CObservationOdometry>(*reading);
        jumped->odometry.x(jumped->odometry.x() + 100);
        glitched.push_back(jumped);
        continue;
      }
    } else if (auto fix = std::dynamic_pointer_cast<mrpt::obs::CObservationGPS>(o)) {
      if (fixes_seen++ == fixes / 3) {
        mrpt::obs::CObservationGPS moved;
        moved.timestamp = fix->timestamp;
        moved.sensorLabel = fix->sensorLabel;
        moved.sensorPose = fix->sensorPose;
        mrpt::obs::gnss::Message_NMEA_GGA gga =
            fix->getMsgByClass<mrpt::obs::gnss::Message_NMEA_GGA>();
        gga.fields.longitude_degrees +=
            50 / (111320 * std::cos(gga.fields.latitude_degrees * M_PI / 180));
        moved.setMsg(gga);
        glitched.push_back(std::make_shared<mrpt::obs::CObservationGPS>(moved));
        continue;
      }
    } else if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) {
      if (gyro_seen++ == gyro / 4) {
        glitched.push_back(o);
        auto ahead = std::make_shared<mrpt::obs::CObservationIMU>(*imu);
        ahead->timestamp = mrpt::Clock::fromDouble(mrpt::Clock::toDouble(imu->timestamp) + 1000);
        glitched.push_back(ahead);
        continue;
      }
    }
    glitched.push_back(o);
  }
  const std::string path = testing::temporary_path("glitched_rover.rawlog");
  std::vector<const mrpt::serialization::CSerializable*> raw;
  for (const auto& o : glitched) raw.push_back(o.get());
  testing::write_plain_rawlog(path, raw);

  const auto replayed = [](const std::string& rawlog, std::size_t* out_of_order) {
    const ReplayInput in = read_replay_input(rawlog, ReplayOptions());
    EXPECT_TRUE(in.read.complete()) << in.read.problem;
    *out_of_order = in.out_of_order;
    sfm::SfmSettings settings;
    settings.batch.covariances = false;
    return std::make_pair(
        sfm::run_fused_sfm(*in.camera, in.tracks, in.frame_times, in.sensors, settings), in);
  };
  std::size_t clean_dropped = 0, dropped = 0;
  const auto [clean, clean_in] = replayed(clean_path, &clean_dropped);
  const auto [result, in] = replayed(path, &dropped);
  EXPECT_EQ(clean_dropped, 0u);
  EXPECT_EQ(dropped, 1u) << "the misdated gyro reading";
  EXPECT_TRUE(clean.refused_motion_frames.empty());
  EXPECT_TRUE(clean.refused_gps_fixes.empty());
  EXPECT_EQ(result.refused_motion_frames.size(), 1u);
  ASSERT_EQ(result.refused_gps_fixes.size(), 1u);
  EXPECT_EQ(result.refused_gps_fixes[0], static_cast<int>(fixes / 3));
  ASSERT_TRUE(result.world_is_enu);
  ASSERT_EQ(result.batch.world_from_cam.size(), clean.batch.world_from_cam.size());
  double apart = 0;
  for (std::size_t f = 0; f < clean.batch.world_from_cam.size(); ++f)
    apart +=
        (result.batch.world_from_cam[f].translation() - clean.batch.world_from_cam[f].translation())
            .norm() /
        static_cast<double>(clean.batch.world_from_cam.size());
  std::printf("the glitched rawlog's batch %.4f m from the clean one's on average\n", apart);
  EXPECT_LT(apart, 0.005);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
