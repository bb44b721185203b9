// The filter's published pose covariance against its actual errors over the simulated rover's
// seeds 1-25, with odometry and gyro (eval::rover_pose_consistency).

#include <gtest/gtest.h>

#include "omnisfm/eval/filter_consistency.h"

namespace omnisfm::sfm {
namespace {

// With a calibrated wheel. Measured: mean 5.25, 92.1 % of 3,725 frames inside. Before the
// smoothed start solved the sensors' states with the poses (it held them, their errors counted as
// new in each frame and their correlations lost): 15.3 and 52 %.
TEST(FilterConsistency, RoverPoseNeesIsHonestWithOdometryAndGyro) {
  const eval::PoseConsistency c = eval::rover_pose_consistency(25, 0.0);
  std::printf("rover seeds 1-25: mean NEES %.2f, %.1f %% inside the 95 %% bound\n", c.mean_nees,
              100 * c.inside);
  EXPECT_GT(c.mean_nees, 4.0);
  EXPECT_LT(c.mean_nees, 8.0);
  EXPECT_GE(c.inside, 0.90);
}

}  // namespace
}  // namespace omnisfm::sfm
