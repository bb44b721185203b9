// The batch leaves the process alone: it runs on the threads its settings give, with the answer
// of one thread on two, and leaves glog's level as the program set it.

#include <glog/logging.h>
#include <gtest/gtest.h>

#include <cmath>

#include <random>

#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sfm {
namespace {

TEST(BatchThreads, TakenFromTheSettingsWithTheSameAnswerAndGlogLeftAlone) {
  const sim::Dataset drive = sim::long_drive(80, 0.2, 3);
  std::mt19937_64 rng(4);
  std::vector<Eigen::Isometry3d> start;
  for (size_t f = 0; f < drive.world_from_cam.size(); ++f) {
    Eigen::Isometry3d world_from_cam = drive.world_from_cam[f];
    if (f > 0)
      world_from_cam.translation() += 0.01 * Eigen::Vector3d(sim::standard_normal(rng),
                                                             sim::standard_normal(rng),
                                                             sim::standard_normal(rng));
    start.push_back(world_from_cam);
  }
  std::map<int, Eigen::Vector3d> start_points;
  for (size_t t = 0; t < drive.track_points.size(); ++t)
    start_points[static_cast<int>(t)] = drive.track_points[t];

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
  // tolerances stop it (two runs stop at iterates 1e-7 m apart, which the heap's layout alone
  // also moves): a thousandth of each translation's own standard deviation, in the coordinates
  // of the covariances.
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

}  // namespace
}  // namespace omnisfm::sfm
