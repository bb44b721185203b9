// The generic starts give the numbers the hand-written starting files derive the same way
// (share/omnisfm/cameras/*-initial.ini), and every corner inside the mirror's picture projects.

#include "omnisfm/calib/starting_camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

namespace omnisfm::calib {
namespace {

double param(const camera::CatadioptricCamera& camera, const std::string& name) {
  const std::vector<std::string> names = camera.param_names();
  const auto found = std::find(names.begin(), names.end(), name);
  EXPECT_NE(found, names.end()) << name;
  return camera.params()[found - names.begin()];
}

MirrorImage circles(double x, double y, double inner, double outer) {
  MirrorImage mirror;
  mirror.centre = Eigen::Vector2d(x, y);
  mirror.inner_radius = inner;
  mirror.outer_radius = outer;
  return mirror;
}

// The picture between the circles unprojects; beyond the rim it does not.
void expect_picture_inside_the_model(const camera::CatadioptricCamera& camera,
                                     const MirrorImage& mirror) {
  Eigen::Vector3d origin, direction;
  for (double fraction : {0.3, 0.6, 0.95}) {
    const double r = mirror.inner_radius + fraction * (mirror.outer_radius - mirror.inner_radius);
    EXPECT_TRUE(camera.unproject(mirror.centre + Eigen::Vector2d(r, 0), &origin, &direction))
        << r;
  }
  EXPECT_FALSE(camera.unproject(
      mirror.centre + Eigen::Vector2d(0, 1.2 * mirror.outer_radius), &origin, &direction));
}

TEST(StartingCamera, HyperbolicBeforeAPinholeAsVmrsFileDerivesIt) {
  // vmr-initial.ini: the picture's edge 448 px out gives fx = 771.4 px.
  const MirrorImage mirror = circles(518, 392, 80, 448);
  const camera::CatadioptricCamera camera =
      starting_camera(mirror, 1024, 768, StartingMirror::kConic, StartingInner::kPinhole);
  EXPECT_NEAR(param(camera, "fx"), 771.4, 0.5);
  EXPECT_EQ(param(camera, "cx"), 518);
  EXPECT_NEAR(camera.mirror_pose().tz, 0.0724264, 1e-6);
  expect_picture_inside_the_model(camera, mirror);
}

TEST(StartingCamera, ParaboloidBeforeATelecentricLensAsItsFileDerivesIt) {
  // paracatadioptric-initial.ini: 354 px out, fx = 12394 px per metre.
  const MirrorImage mirror = circles(642, 520, 55, 354);
  const camera::CatadioptricCamera camera =
      starting_camera(mirror, 1280, 1024, StartingMirror::kConic, StartingInner::kOrthographic);
  EXPECT_NEAR(param(camera, "fx"), 12394, 5);
  expect_picture_inside_the_model(camera, mirror);
}

TEST(StartingCamera, EquiangularBeforeAPinholeAsKaidansFileDerivesIt) {
  // kaidan-initial.ini: a 640 px webcam, 225 px out: fx 686, alpha 7.7.
  const MirrorImage mirror = circles(324.5, 246, 57, 225);
  const camera::CatadioptricCamera camera =
      starting_camera(mirror, 640, 480, StartingMirror::kEquiangular, StartingInner::kPinhole);
  EXPECT_NEAR(param(camera, "fx"), 686, 0.5);
  EXPECT_NEAR(param(camera, "equiangular_alpha"), 7.7, 0.02);
  expect_picture_inside_the_model(camera, mirror);
}

TEST(StartingCamera, RefusesWhatItHasNoStartFor) {
  EXPECT_THROW(starting_camera(circles(320, 240, 50, 200), 640, 480,
                               StartingMirror::kEquiangular, StartingInner::kOrthographic),
               std::invalid_argument);
  EXPECT_THROW(starting_camera(circles(320, 240, 200, 50), 640, 480, StartingMirror::kConic,
                               StartingInner::kPinhole),
               std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::calib
