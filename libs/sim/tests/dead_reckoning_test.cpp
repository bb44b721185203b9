// Simulated odometry and gyro: exact without noise, and with their stated drift otherwise.

#include "omnisfm/sim/dead_reckoning.h"

#include <gtest/gtest.h>

#include <cmath>

#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/trajectories.h"

namespace omnisfm::sim {
namespace {

Dataset dataset_of(const std::string& scenario) {
  SimulationOptions options;
  options.scenario = scenario;
  return simulate(options);
}

DeadReckoningOptions perfect_sensors() {
  DeadReckoningOptions o;
  o.odometry_scale_error = o.odometry_yaw_scale_error = 0;
  o.odometry_position_noise = o.odometry_heading_noise = 0;
  o.gyro_noise_density = o.gyro_bias_sigma = o.gyro_bias_walk = 0;
  return o;
}

Eigen::Vector3d planar(const Eigen::Isometry3d& T) {
  return {T.translation().x(), T.translation().y(), std::atan2(T.linear()(1, 0), T.linear()(0, 0))};
}

Eigen::Matrix3d integrate(const std::vector<GyroReading>& gyro) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  for (size_t j = 0; j + 1 < gyro.size(); ++j) {
    const Eigen::Vector3d angle = gyro[j].rate * (gyro[j + 1].timestamp - gyro[j].timestamp);
    if (angle.norm() > 0)
      R = R * Eigen::AngleAxisd(angle.norm(), angle.normalized()).toRotationMatrix();
  }
  return R;
}

class PerfectSensors : public ::testing::TestWithParam<std::string> {};

TEST_P(PerfectSensors, ReproduceTheTrueMotion) {
  const Dataset d = dataset_of(GetParam());
  const DeadReckoning dr = simulate_dead_reckoning(d, perfect_sensors());
  const Eigen::Isometry3d cam_from_body = dr.body_from_cam.inverse();
  const Eigen::Isometry3d world_from_body0 = d.world_from_cam.front() * cam_from_body;
  const Eigen::Isometry3d world_from_body1 = d.world_from_cam.back() * cam_from_body;

  if (GetParam() == "crane") {
    EXPECT_TRUE(dr.odometry.empty()) << "the crane's motion is not planar";
  } else {
    ASSERT_FALSE(dr.odometry.empty());
    const Eigen::Vector3d expected = planar(world_from_body0.inverse() * world_from_body1);
    EXPECT_NEAR(dr.odometry.back().timestamp, d.timestamps.back(), 1e-9);
    EXPECT_LT((dr.odometry.back().pose - expected).norm(), 1e-9);
  }
  ASSERT_GT(dr.gyro.size(), 10u);
  const Eigen::Matrix3d expected_rotation =
      world_from_body0.linear().transpose() * world_from_body1.linear();
  EXPECT_LT((integrate(dr.gyro) - expected_rotation).norm(), 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Scenarios, PerfectSensors, ::testing::Values("lab", "crane", "rover"));

TEST(DeadReckoning, BodyIsUprightForEveryRig) {
  // The lab's rig hangs upside down: its body frame is the camera's turned about x.
  const DeadReckoning lab = simulate_dead_reckoning(dataset_of("lab"), perfect_sensors());
  EXPECT_LT(
      (lab.body_from_cam.linear() - Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix()).norm(),
      1e-15);
  for (const auto& reading : lab.odometry) EXPECT_NEAR(reading.pose.z(), 0, 1e-12);
  const DeadReckoning rover = simulate_dead_reckoning(dataset_of("rover"), perfect_sensors());
  EXPECT_TRUE(rover.body_from_cam.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(DeadReckoning, OdometryDriftsAsStated) {
  const Dataset d = dataset_of("rover");
  const DeadReckoningOptions options;
  const DeadReckoning dr = simulate_dead_reckoning(d, options);
  double read_length = 0;
  for (size_t i = 1; i < dr.odometry.size(); ++i)
    read_length += (dr.odometry[i].pose.head<2>() - dr.odometry[i - 1].pose.head<2>()).norm();
  const double true_length = path_length(d.world_from_cam);
  EXPECT_NEAR(read_length / true_length, 1 + options.odometry_scale_error, 0.003);

  const Eigen::Vector3d truth =
      planar(d.world_from_cam.front().inverse() * d.world_from_cam.back());
  const double end_error = (dr.odometry.back().pose.head<2>() - truth.head<2>()).norm();
  EXPECT_GT(end_error / true_length, 0.005);
  EXPECT_LT(end_error / true_length, 0.05);
}

TEST(DeadReckoning, GyroCarriesItsBias) {
  const Dataset d = dataset_of("rover");
  const DeadReckoning noisy = simulate_dead_reckoning(d, DeadReckoningOptions{});
  const DeadReckoning perfect = simulate_dead_reckoning(d, perfect_sensors());
  ASSERT_EQ(noisy.gyro.size(), perfect.gyro.size());
  Eigen::Vector3d mean_error = Eigen::Vector3d::Zero();
  for (size_t j = 0; j < noisy.gyro.size(); ++j)
    mean_error += noisy.gyro[j].rate - perfect.gyro[j].rate;
  mean_error /= static_cast<double>(noisy.gyro.size());
  EXPECT_GT(noisy.gyro_bias_at_start.norm(), 1e-4);
  // The bias wanders by about 2e-5 * sqrt(75 s); the white noise averages to ~2e-5.
  EXPECT_LT((mean_error - noisy.gyro_bias_at_start).norm(), 1e-3);
}

TEST(DeadReckoning, DeterministicForASeed) {
  const Dataset d = dataset_of("lab");
  DeadReckoningOptions options;
  const DeadReckoning a = simulate_dead_reckoning(d, options);
  const DeadReckoning b = simulate_dead_reckoning(d, options);
  options.seed = 2;
  const DeadReckoning c = simulate_dead_reckoning(d, options);
  EXPECT_EQ(a.odometry.back().pose, b.odometry.back().pose);
  EXPECT_EQ(a.gyro.back().rate, b.gyro.back().rate);
  EXPECT_NE(a.odometry.back().pose, c.odometry.back().pose);
}

// An exposure about the first or last frame reaches past the sequence: the rig's motion goes on
// there (the rover drives at a constant speed), where interpolate_pose stops at the end frames.
TEST(DeadReckoning, ExtrapolatedPoseContinuesTheMotionPastTheEnds) {
  const Dataset d = dataset_of("rover");
  const double interval = d.timestamps[1] - d.timestamps[0];
  for (const double t : {d.timestamps[0] + 0.3 * interval, d.timestamps[5]})
    EXPECT_TRUE(extrapolate_pose(d, t).isApprox(interpolate_pose(d, t), 1e-12));
  const Eigen::Vector3d before = extrapolate_pose(d, d.timestamps[0] - 0.25 * interval).translation();
  const Eigen::Vector3d step = d.world_from_cam[1].translation() - d.world_from_cam[0].translation();
  EXPECT_LT((before - (d.world_from_cam[0].translation() - 0.25 * step)).norm(), 1e-9);
  const size_t last = d.timestamps.size() - 1;
  const Eigen::Vector3d after =
      extrapolate_pose(d, d.timestamps[last] + 0.25 * interval).translation();
  const Eigen::Vector3d last_step =
      d.world_from_cam[last].translation() - d.world_from_cam[last - 1].translation();
  EXPECT_LT((after - (d.world_from_cam[last].translation() + 0.25 * last_step)).norm(), 1e-9);
  EXPECT_TRUE(interpolate_pose(d, d.timestamps[0] - interval).isApprox(d.world_from_cam[0]));
}

TEST(DeadReckoning, RejectsNonsense) {
  Dataset d = dataset_of("lab");
  DeadReckoningOptions options;
  options.gyro_rate_hz = 0;
  EXPECT_THROW(simulate_dead_reckoning(d, options), std::invalid_argument);
  options = {};
  options.odometry_heading_noise = -1;
  EXPECT_THROW(simulate_dead_reckoning(d, options), std::invalid_argument);
  d.timestamps[3] = d.timestamps[2];
  EXPECT_THROW(simulate_dead_reckoning(d, DeadReckoningOptions{}), std::invalid_argument);
}

// Streamed frame by frame along an endless drive, the odometry is the one the whole dataset gives
// (the same draws); the gyro, on a generator of its own, has the same times and its own bias.
TEST(DeadReckoningStream, ReadsADriveAsTheWholeDatasetWould) {
  const Dataset d = long_drive(200, 0.2, 3);
  DeadReckoningOptions options;
  options.seed = 3;
  const DeadReckoning whole = simulate_dead_reckoning(d, options);
  DeadReckoningStream stream(body_from_cam(d), options, true);
  std::vector<OdometryReading> odometry;
  std::vector<GyroReading> gyro;
  for (size_t f = 0; f < d.world_from_cam.size(); ++f) {
    const size_t before = odometry.size();
    stream.add_frame(d.timestamps[f], d.world_from_cam[f], &odometry, &gyro);
    // Each frame brings the readings since the previous one: 10 Hz odometry, 2 fps frames.
    EXPECT_EQ(odometry.size() - before, f == 0 ? 0u : 5u);
    if (f > 0) {
      EXPECT_LT(odometry.back().timestamp, d.timestamps[f]);
    }
  }
  stream.finish(&odometry, &gyro);
  ASSERT_EQ(odometry.size(), whole.odometry.size());
  for (size_t k = 0; k < odometry.size(); ++k) {
    EXPECT_EQ(odometry[k].timestamp, whole.odometry[k].timestamp);
    EXPECT_EQ(odometry[k].pose, whole.odometry[k].pose);
  }
  ASSERT_EQ(gyro.size(), whole.gyro.size());
  for (size_t k = 0; k < gyro.size(); ++k) EXPECT_EQ(gyro[k].timestamp, whole.gyro[k].timestamp);
  EXPECT_NE(stream.gyro_bias_at_start(), whole.gyro_bias_at_start);
  // The gyro's mean error is its bias (the walk moves it by about 2e-5 sqrt(100 s) = 2e-4 rad/s).
  Eigen::Vector3d error_sum(0, 0, 0);
  for (size_t k = 0; k < gyro.size(); ++k) {
    const size_t f = std::min<size_t>(static_cast<size_t>(gyro[k].timestamp / 0.5), 198);
    const Eigen::AngleAxisd step(d.world_from_cam[f].linear().transpose() *
                                 d.world_from_cam[f + 1].linear());
    error_sum += gyro[k].rate - step.angle() * step.axis() / 0.5;
  }
  EXPECT_LT((error_sum / gyro.size() - stream.gyro_bias_at_start()).norm(), 1e-3);
  EXPECT_GT(stream.gyro_bias_at_start().norm(), 1e-4);
  EXPECT_THROW(stream.add_frame(d.timestamps[0], d.world_from_cam[0], &odometry, &gyro),
               std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
