// The rawlog for stock SLAM apps: the bearing-range measurements' geometry and derivatives, and the
// file read back by MRPT as kf-slam reads it (stock kf-slam itself runs on it in
// kf_slam_follows_truth).

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <unistd.h>

#include <filesystem>
#include <random>

#include "eigen_poses.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/mrpt_plugin/pose_graph_file.h"
#include "omnisfm/mrpt_plugin/slam_rawlog.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::mrpt_plugin {
namespace {

sim::Dataset simulated(const std::string& scenario, double noise_px) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.tracking_noise_px = noise_px;
  return sim::simulate(options);
}

std::vector<core::TrackObservation> of_frame(const sim::Dataset& d, int frame) {
  std::vector<core::TrackObservation> observations;
  for (const auto& o : d.observations)
    if (o.frame == frame) observations.push_back(o);
  return observations;
}

std::map<int, Eigen::Vector3d> true_points(const sim::Dataset& d) {
  std::map<int, Eigen::Vector3d> points;
  for (size_t t = 0; t < d.track_points.size(); ++t) points[static_cast<int>(t)] = d.track_points[t];
  return points;
}

TEST(SphericalCoordinates, AreMrptsAndTheirJacobianMatchesCentralDifferences) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> coordinate(-5, 5);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d p(coordinate(random), coordinate(random), coordinate(random));
    Eigen::Matrix3d J;
    const Eigen::Vector3d rpy = spherical_coordinates(p, &J);
    double range, yaw, pitch;
    mrpt::poses::CPose3D().sphericalCoordinates(mrpt::math::TPoint3D(p.x(), p.y(), p.z()), range,
                                                yaw, pitch);
    EXPECT_NEAR(rpy[0], range, 1e-12);
    EXPECT_NEAR(rpy[1], yaw, 1e-12);
    EXPECT_NEAR(rpy[2], pitch, 1e-12);
    const double h = 1e-6;
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(axis);
      const Eigen::Vector3d numeric =
          (spherical_coordinates(p + step) - spherical_coordinates(p - step)) / (2 * h);
      EXPECT_LT((J.col(axis) - numeric).norm(), 1e-7) << p.transpose() << " axis " << axis;
    }
  }
}

// Noise-free pixels of the true points, seen from the true poses: the point on each pixel's ray
// is the true point, whatever its depth estimate along the ray.
TEST(BearingRange, AreThePointsOwnCoordinatesOnTheirRays) {
  const sim::Dataset d = simulated("rover", 0);
  const int frame = 40;
  const Eigen::Isometry3d cam_from_world = d.world_from_cam[frame].inverse();
  std::map<int, Eigen::Vector3d> points = true_points(d);
  const std::vector<core::TrackObservation> observations = of_frame(d, frame);
  sfm::BatchResult batch;
  batch.world_from_cam.assign(d.world_from_cam.size(), Eigen::Isometry3d::Identity());
  batch.world_from_cam[frame] = d.world_from_cam[frame];
  batch.cam_from_world_parameters.assign(d.world_from_cam.size(), core::PoseVector::Zero());
  batch.cam_from_world_parameters[frame] = core::pose_vector_of(cam_from_world);
  batch.points = points;
  const std::vector<BearingRange> exact =
      bearing_range_measurements(d.camera, batch, frame, observations, 0.2);
  ASSERT_GT(exact.size(), 30u);
  int checked = 0;
  for (const BearingRange& m : exact) {
    if (m.track >= static_cast<int>(d.track_points.size()))
      continue;
    const bool outlier = std::any_of(d.outliers.begin(), d.outliers.end(),
                                     [&](const auto& o) { return o.track == m.track; });
    if (outlier) continue;
    const Eigen::Vector3d truth = spherical_coordinates(cam_from_world * points[m.track]);
    EXPECT_NEAR(m.range, truth[0], 1e-6);
    EXPECT_NEAR(m.yaw, truth[1], 1e-7);
    EXPECT_NEAR(m.pitch, truth[2], 1e-7);
    // Only the pixel's noise: bearings of a few hundredths of a degree at 0.2 px, and a range
    // that moves only with the ray's origin on the mirror (a tenth of a millimetre).
    EXPECT_LT(std::sqrt(m.covariance(0, 0)), 1e-3);
    EXPECT_GT(std::sqrt(m.covariance(1, 1)), 1e-5);
    EXPECT_LT(std::sqrt(m.covariance(1, 1)), 1e-2);
    ++checked;
  }
  EXPECT_GT(checked, 30);

  // Each point moved off its ray by 5 cm and along it by 10 cm: the measurement is the point on
  // the pixel's ray nearest it (its bearing changes too: the ray misses the camera's origin), and
  // the point's uncertainty becomes the range's.
  std::map<int, Eigen::Matrix3d> covariances;
  std::map<int, Eigen::Vector3d> shifts;
  for (const BearingRange& m : exact) {
    const Eigen::Vector3d in_camera = cam_from_world * points[m.track];
    const Eigen::Vector3d along = in_camera.normalized();
    shifts[m.track] = 0.05 * along.unitOrthogonal() + 0.1 * along;
    points[m.track] = cam_from_world.inverse() * (in_camera + shifts[m.track]);
    covariances[m.track] = 0.01 * 0.01 * Eigen::Matrix3d::Identity();
  }
  batch.points = points;
  batch.point_covariances = covariances;
  const std::vector<BearingRange> moved =
      bearing_range_measurements(d.camera, batch, frame, observations, 0.2);
  ASSERT_EQ(moved.size(), exact.size());
  const auto cartesian = [](const BearingRange& m) {
    return Eigen::Vector3d(m.range * std::cos(m.pitch) * std::cos(m.yaw),
                           m.range * std::cos(m.pitch) * std::sin(m.yaw),
                           -m.range * std::sin(m.pitch));
  };
  for (size_t i = 0; i < moved.size(); ++i) {
    const auto pixel = std::find_if(observations.begin(), observations.end(),
                                    [&](const auto& o) { return o.track == moved[i].track; });
    Eigen::Vector3d origin, direction;
    ASSERT_TRUE(d.camera.unproject(pixel->pixel, &origin, &direction));
    const Eigen::Vector3d on_ray = cartesian(moved[i]) - origin;
    EXPECT_LT((on_ray - on_ray.dot(direction) * direction).norm(), 1e-5);
    EXPECT_NEAR((cartesian(moved[i]) - cartesian(exact[i])).dot(direction),
                shifts[moved[i].track].dot(direction), 1e-5);
    EXPECT_NEAR(std::sqrt(moved[i].covariance(0, 0)), 0.01, 0.002);
  }
}

std::string temporary_rawlog(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("omnisfm_") + name + "_" + std::to_string(::getpid()) + ".rawlog"))
      .string();
}

// The rawlog read back as kf-slam reads it: an action and a sensory frame per batch frame, the
// increments the robot's (a camera mounted upside down, off the robot's origin), the measurements
// the tracks the batch kept.
TEST(SlamRawlog, IsReadByMrptAsActionsAndObservationPairs) {
  const sim::Dataset d = simulated("rover", 0.2);
  const sfm::SfmResult r = sfm::run_sfm(d.camera, d.observations, sfm::SfmSettings{});
  ASSERT_TRUE(r.batch.converged);
  Eigen::Isometry3d body_from_cam = Eigen::Isometry3d::Identity();
  body_from_cam.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  body_from_cam.translation() << 0.1, 0, 0.5;
  std::vector<double> times;
  for (double t : d.timestamps) times.push_back(1e9 + t);
  times.resize(r.batch.world_from_cam.size());
  const std::string path = temporary_rawlog("slam");
  const SlamRawlogSummary summary =
      write_slam_rawlog(path, d.camera, d.observations, r.batch, times, body_from_cam, 0.2);
  EXPECT_EQ(summary.frames, static_cast<int>(times.size()));

  const std::vector<PoseGraphEdge> increments = consecutive_edges(r.batch, body_from_cam);
  mrpt::io::CFileGZInputStream file(path);
  auto archive = mrpt::serialization::archiveFrom(file);
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr frame;
  size_t entry = 0, pairs = 0;
  long measurements = 0;
  Eigen::Isometry3d robot = Eigen::Isometry3d::Identity();
  while (mrpt::obs::CRawlog::readActionObservationPair(archive, actions, frame, entry)) {
    const auto movement = actions->getActionByClass<mrpt::obs::CActionRobotMovement3D>();
    ASSERT_TRUE(movement);
    const Eigen::Isometry3d increment = isometry_of(movement->poseChange.mean);
    robot = robot * increment;
    if (pairs > 0) {
      const PoseGraphEdge& edge = increments[pairs - 1];
      EXPECT_LT((increment.matrix() - edge.relative.matrix()).norm(), 1e-9);
      EXPECT_LT((movement->poseChange.cov.asEigen() - edge.covariance).norm(),
                1e-9 * edge.covariance.norm());
    }
    const auto landmarks = frame->getObservationByClass<mrpt::obs::CObservationBearingRange>();
    ASSERT_TRUE(landmarks);
    EXPECT_EQ(landmarks->sensorLabel, kLandmarksLabel);
    EXPECT_NEAR(mrpt::Clock::toDouble(landmarks->timestamp), times[pairs], 1e-5);
    EXPECT_LT((isometry_of(landmarks->sensorLocationOnRobot).matrix() - body_from_cam.matrix())
                  .norm(),
              1e-12);
    EXPECT_TRUE(landmarks->validCovariances);
    for (const auto& m : landmarks->sensedData) {
      // A track the batch kept: adjusted (with its covariance), not an outlier.
      EXPECT_EQ(r.batch.point_covariances.count(m.landmarkID), 1u) << m.landmarkID;
      EXPECT_TRUE(std::none_of(r.outliers.begin(), r.outliers.end(),
                               [&](const auto& o) { return o.track == m.landmarkID; }))
          << m.landmarkID;
      EXPECT_GT(m.range, 0);
      EXPECT_GT(m.covariance(0, 0), 0);
    }
    measurements += static_cast<long>(landmarks->sensedData.size());
    ++pairs;
  }
  EXPECT_EQ(pairs, times.size());
  EXPECT_EQ(measurements, summary.measurements);
  EXPECT_GT(measurements, 100 * static_cast<long>(pairs) / 2);
  // The increments compose into the robot's last pose relative to its first.
  const Eigen::Isometry3d last = body_from_cam * r.batch.world_from_cam.front().inverse() *
                                 r.batch.world_from_cam.back() * body_from_cam.inverse();
  EXPECT_LT((robot.matrix() - last.matrix()).norm(), 1e-6);
  std::filesystem::remove(path);

  times.pop_back();
  EXPECT_THROW(
      write_slam_rawlog(path, d.camera, d.observations, r.batch, times, body_from_cam, 0.2),
      std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
