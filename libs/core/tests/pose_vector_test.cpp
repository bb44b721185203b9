// The solvers' six numbers and the transform they stand for go back and forth exactly enough,
// near the identity and near a half turn, and mean X' = R(aa) X + t.

#include "omnisfm/core/pose_vector.h"

#include <gtest/gtest.h>

#include <cmath>

namespace omnisfm::core {
namespace {

TEST(PoseVector, RoundTripsAndTransformsAsItSays) {
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.8, 0.5).normalized();
  for (const double angle : {0.0, 1e-9, 0.4, 2.0, M_PI - 1e-6}) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    T.translation() = Eigen::Vector3d(1.5, -0.2, 0.7);
    const PoseVector v = pose_vector_of(T);
    EXPECT_NEAR(v.head<3>().norm(), angle, 1e-12) << angle;
    if (angle > 0) {
      EXPECT_LT((v.head<3>().normalized() - axis).norm(), 1e-6) << angle;
    }
    EXPECT_EQ(v.tail<3>(), T.translation());
    const Eigen::Isometry3d back = isometry_of(v);
    EXPECT_LT((back.matrix() - T.matrix()).norm(), 1e-12) << angle;
    const Eigen::Vector3d X(0.1, 2.0, -3.0);
    EXPECT_LT((isometry_of(v.data()) * X - T * X).norm(), 1e-12) << angle;
  }
}

}  // namespace
}  // namespace omnisfm::core
