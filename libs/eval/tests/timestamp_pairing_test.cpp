// Poses pair by time: only the times both trajectories hold, within the tolerance, each once.

#include "omnisfm/eval/timestamp_pairing.h"

#include <gtest/gtest.h>

namespace omnisfm::eval {
namespace {

std::vector<io::StampedPose> trajectory(const std::vector<double>& times) {
  std::vector<io::StampedPose> poses;
  for (const double t : times) {
    io::StampedPose p;
    p.timestamp = t;
    p.world_from_cam.translation() = Eigen::Vector3d(t, 0, 0);
    poses.push_back(p);
  }
  return poses;
}

TEST(TimestampPairing, PairsTheTimesBothHold) {
  const auto estimate = trajectory({0.0, 0.1, 0.2 + 5e-7, 0.35, 0.4});
  const auto truth = trajectory({0.1, 0.2, 0.3, 0.4, 0.5});
  const PairedPoses paired = pair_by_timestamp(estimate, truth);
  ASSERT_EQ(paired.estimate.size(), 3u);
  ASSERT_EQ(paired.truth.size(), 3u);
  EXPECT_EQ(paired.estimate[0].translation().x(), 0.1);
  EXPECT_EQ(paired.truth[1].translation().x(), 0.2);
  EXPECT_EQ(paired.estimate[1].translation().x(), 0.2 + 5e-7);
  EXPECT_EQ(paired.truth[2].translation().x(), 0.4);
  EXPECT_TRUE(pair_by_timestamp(estimate, trajectory({1e9, 1e9 + 0.1})).estimate.empty());
}

}  // namespace
}  // namespace omnisfm::eval
