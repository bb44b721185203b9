#include "omnisfm/sim/scene.h"

#include <gtest/gtest.h>

namespace omnisfm::sim {
namespace {

TEST(Scene, NearestSurfaceWithItsCoordinates) {
  Scene scene;
  scene.add_box({0, 0, 0}, {2, 3, 4}, 7);
  scene.add_marker({{1, 1.5, 3.999}, {0, 0, -1}, 0.1, 5});
  SceneHit hit;
  // From inside, straight up: the marker before the ceiling.
  ASSERT_TRUE(scene.intersect({1, 1.5, 1}, {0, 0, 1}, 100, &hit));
  EXPECT_EQ(hit.marker, 0);
  EXPECT_NEAR(hit.distance, 2.999, 1e-12);
  EXPECT_NEAR(hit.uv.norm(), 0, 1e-12);
  // Sideways to the wall x = 2, at height 1 and y = 0.5 along the wall's edges.
  ASSERT_TRUE(scene.intersect({1, 0.5, 1}, {1, 0, 0}, 100, &hit));
  EXPECT_EQ(hit.marker, -1);
  EXPECT_EQ(scene.quads()[hit.quad].texture, 7);
  EXPECT_NEAR(hit.distance, 1, 1e-12);
  EXPECT_NEAR(hit.uv.x(), 0.5, 1e-12);
  EXPECT_NEAR(hit.uv.y(), 1, 1e-12);
  // Nothing closer than max_distance.
  EXPECT_FALSE(scene.intersect({1, 0.5, 1}, {1, 0, 0}, 0.9, &hit));
  // From outside, away from the box: nothing.
  EXPECT_FALSE(scene.intersect({5, 5, 5}, {1, 0, 0}, 100, &hit));
}

TEST(Scene, VisibilityIsBlockedOnlyByWhatLiesBetween) {
  Scene scene;
  scene.add_box({1, -0.5, 0}, {2, 0.5, 1}, 0);
  EXPECT_FALSE(scene.visible({0, 0, 0.5}, {3, 0, 0.5}));
  EXPECT_TRUE(scene.visible({0, 0, 0.5}, {0, 3, 0.5}));
  // A point on the box's face is seen from in front of it.
  EXPECT_TRUE(scene.visible({0, 0, 0.5}, {1, 0, 0.5}));
  EXPECT_FALSE(scene.visible({0, 0, 0.5}, {2, 0, 0.5}));  // its far face is hidden
}

}  // namespace
}  // namespace omnisfm::sim
