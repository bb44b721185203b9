// A trajectory turned the other way round: each pose composes with its counterpart to the
// identity, in order, and turned back it is the trajectory it was.

#include "omnisfm/core/pose_direction.h"

#include <gtest/gtest.h>

namespace omnisfm::core {
namespace {

TEST(PoseDirection, InvertedIsEachPoseTheOtherWayRound) {
  std::vector<Eigen::Isometry3d> world_from_cam;
  for (int k = 0; k < 4; ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() =
        Eigen::AngleAxisd(0.7 * k, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
    T.translation() = Eigen::Vector3d(k, -0.5 * k, 1.0 / 3);
    world_from_cam.push_back(T);
  }
  const std::vector<Eigen::Isometry3d> cam_from_world = inverted(world_from_cam);
  ASSERT_EQ(cam_from_world.size(), world_from_cam.size());
  const std::vector<Eigen::Isometry3d> back = inverted(cam_from_world);
  for (size_t k = 0; k < world_from_cam.size(); ++k) {
    EXPECT_TRUE((cam_from_world[k] * world_from_cam[k]).matrix().isIdentity(1e-12)) << k;
    EXPECT_LT((back[k].matrix() - world_from_cam[k].matrix()).norm(), 1e-12) << k;
  }
  EXPECT_TRUE(inverted({}).empty());
}

}  // namespace
}  // namespace omnisfm::core
