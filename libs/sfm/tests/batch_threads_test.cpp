// The batch leaves the process alone: it runs on the threads its settings give, with the answer
// of one thread on two, and leaves glog's level as the program set it. On one thread it gives the
// same digits however the heap lies.

#include <glog/logging.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "imperfect_calibration.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sfm {
namespace {

// The drive's truth, its positions disturbed by 1 cm: the batch's start.
struct DisturbedStart {
  std::vector<Eigen::Isometry3d> poses;
  std::map<int, Eigen::Vector3d> points;
};

DisturbedStart disturbed_start(const sim::Dataset& drive) {
  std::mt19937_64 rng(4);
  DisturbedStart start;
  for (size_t f = 0; f < drive.world_from_cam.size(); ++f) {
    Eigen::Isometry3d world_from_cam = drive.world_from_cam[f];
    if (f > 0)
      world_from_cam.translation() += 0.01 * Eigen::Vector3d(sim::standard_normal(rng),
                                                             sim::standard_normal(rng),
                                                             sim::standard_normal(rng));
    start.poses.push_back(world_from_cam);
  }
  for (size_t t = 0; t < drive.track_points.size(); ++t)
    start.points[static_cast<int>(t)] = drive.track_points[t];
  return start;
}

TEST(BatchThreads, TakenFromTheSettingsWithTheSameAnswerAndGlogLeftAlone) {
  const sim::Dataset drive = sim::long_drive(80, 0.2, 3);
  const DisturbedStart disturbed = disturbed_start(drive);
  const std::vector<Eigen::Isometry3d>& start = disturbed.poses;
  const std::map<int, Eigen::Vector3d>& start_points = disturbed.points;

  const int program_level = FLAGS_minloglevel;
  FLAGS_minloglevel = google::GLOG_INFO;
  BatchSettings settings;
  settings.threads = 1;
  const BatchResult one = batch_adjust(drive.camera, drive.observations, start, start_points,
                                       settings);
  settings.threads = 2;
  const BatchResult two = batch_adjust(drive.camera, drive.observations, start, start_points,
                                       settings);
  EXPECT_EQ(FLAGS_minloglevel, google::GLOG_INFO);
  FLAGS_minloglevel = program_level;

  ASSERT_TRUE(one.converged) << one.message;
  ASSERT_TRUE(two.converged) << two.message;
  // Threads change only the order of Ceres' sums: the same minimum, up to where the solver's
  // tolerances stop it (two runs stop at iterates 1e-7 m apart): a thousandth of each translation's
  // own standard deviation, in the coordinates of the covariances.
  EXPECT_NEAR(one.final_rms_px, two.final_rms_px, 1e-9 * one.final_rms_px);
  ASSERT_EQ(one.cam_from_world_parameters.size(), two.cam_from_world_parameters.size());
  ASSERT_EQ(one.cam_from_world_covariances.size(), one.cam_from_world_parameters.size());
  for (size_t f = 1; f < one.cam_from_world_parameters.size(); ++f)
    EXPECT_LT((one.cam_from_world_parameters[f].tail<3>() -
               two.cam_from_world_parameters[f].tail<3>())
                  .norm(),
              1e-3 * std::sqrt(one.cam_from_world_covariances[f].bottomRightCorner<3, 3>().trace()))
        << "frame " << f;
  ASSERT_EQ(one.cam_from_world_covariances.size(), two.cam_from_world_covariances.size());
  for (size_t f = 0; f < one.cam_from_world_covariances.size(); ++f)
    EXPECT_LT((one.cam_from_world_covariances[f] - two.cam_from_world_covariances[f]).norm(),
              1e-6 * one.cam_from_world_covariances[f].norm() + 1e-15)
        << "frame " << f;
}

// Ceres eliminates the points in the order of their addresses: held where the heap put each, the
// same start gave iterates 1e-7 m apart between runs (TrackPoints).
TEST(BatchThreads, OneThreadGivesTheSameDigitsWhereverTheHeapPutsThePoints) {
  const sim::Dataset drive = sim::long_drive(80, 0.2, 3);
  const DisturbedStart start = disturbed_start(drive);
  BatchSettings settings;
  settings.threads = 1;
  settings.covariances = false;
  // The camera refined too (its block is wherever the heap put it), at the true distance.
  BatchSettings refining = settings;
  refining.camera_prior = lab_target_calibration_prior(drive.camera);
  refining.known_distance_m =
      (drive.world_from_cam.back().translation() - drive.world_from_cam.front().translation())
          .norm();
  for (const BatchSettings& s : {settings, refining}) {
    const BatchResult first =
        batch_adjust(drive.camera, drive.observations, start.poses, start.points, s);
    ASSERT_TRUE(first.converged) << first.message;
    // Blocks of assorted sizes left between freed ones, held through the second run: its
    // allocations land elsewhere, in another order.
    std::vector<std::vector<char>> kept;
    for (int k = 0; k < 3000; ++k) {
      std::vector<char> block(static_cast<size_t>(24 + (k * 37) % 200));
      if (k % 3 == 0) kept.push_back(std::move(block));
    }
    const BatchResult second =
        batch_adjust(drive.camera, drive.observations, start.poses, start.points, s);
    ASSERT_TRUE(second.converged) << second.message;
    EXPECT_EQ(first.camera_refined, !s.camera_prior.empty());
    EXPECT_EQ(second.camera_refined, first.camera_refined);
    EXPECT_EQ(first.iterations, second.iterations);
    EXPECT_EQ(first.camera_params, second.camera_params);
    ASSERT_EQ(first.cam_from_world_parameters.size(), second.cam_from_world_parameters.size());
    for (size_t f = 0; f < first.cam_from_world_parameters.size(); ++f)
      EXPECT_EQ(first.cam_from_world_parameters[f], second.cam_from_world_parameters[f])
          << "frame " << f;
    ASSERT_EQ(first.points.size(), second.points.size());
    for (const auto& [track, p] : first.points) EXPECT_EQ(p, second.points.at(track)) << track;
  }
}

}  // namespace
}  // namespace omnisfm::sfm
