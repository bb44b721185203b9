#include "omnisfm/calib/starting_camera.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/orthographic_camera.h"
#include "omnisfm/camera/pinhole_camera.h"

namespace omnisfm::calib {

namespace {

constexpr double kDegree = M_PI / 180;

// A generic hyperbolic mirror before a pinhole at its outer focus: radius of curvature 30 mm at
// the apex, conic constant -2, the pinhole A (1 + sqrt 2) = 72.4 mm below the apex. Such cameras
// see up to some 20-30 degrees above the plane through the inner focus; the rim at 25 degrees
// (rho 67.6 mm, z 43.9 mm) must image on the picture's edge, which sets the focal length. The
// mirror's size trades against its distance, so these guesses fix only the scale of the
// mirror-to-camera transform, which the calibration holds.
camera::CatadioptricCamera hyperbolic_start(const MirrorImage& mirror, int width, int height) {
  constexpr double kApexRadius = 0.03, kConic = -2;
  const double tz = kApexRadius * (1 + std::sqrt(2.0));
  const double c = 1 / kApexRadius;
  const auto z = [&](double rho) {
    return c * rho * rho / (1 + std::sqrt(1 - (1 + kConic) * c * c * rho * rho));
  };
  // The inner focus A (sqrt 2 - 1) beyond the apex; the rim at the mirror point seen from it 25
  // degrees above its plane (bisection: z - focus - rho tan 25 deg grows with rho, the
  // asymptote's slope being 1).
  const double focus_z = kApexRadius * (std::sqrt(2.0) - 1);
  double lo = 0, hi = 1;
  for (int i = 0; i < 60; ++i) {
    const double mid = (lo + hi) / 2;
    (z(mid) - focus_z - mid * std::tan(25 * kDegree) < 0 ? lo : hi) = mid;
  }
  const double rho = (lo + hi) / 2, rim_z = z(rho);
  camera::PinholeIntrinsics lens;
  lens.fx = lens.fy = mirror.outer_radius * (rim_z + tz) / rho;
  lens.cx = mirror.centre.x();
  lens.cy = mirror.centre.y();
  camera::MirrorPose pose;
  pose.tz = tz;
  return {std::make_unique<camera::PinholeCamera>(lens),
          std::make_unique<camera::ConicProfile>(0, c, kConic, 0.001, rho), pose, width, height};
}

// A paraboloid before a telecentric lens: radius of curvature 20 mm at the apex (focus 10 mm
// above it); its rim seeing 20 degrees above the horizon, rho = 0.02 tan 55 deg, images on the
// picture's edge: the lens's pixels per metre.
camera::CatadioptricCamera parabolic_start(const MirrorImage& mirror, int width, int height) {
  constexpr double kApexRadius = 0.02;
  const double rim_rho = kApexRadius * std::tan(55 * kDegree);
  camera::OrthographicIntrinsics lens;
  lens.fx = lens.fy = mirror.outer_radius / rim_rho;
  lens.cx = mirror.centre.x();
  lens.cy = mirror.centre.y();
  camera::MirrorPose pose;
  pose.tz = 0.1;  // a telecentric lens does not see it; the calibration holds it
  return {std::make_unique<camera::OrthographicCamera>(lens),
          std::make_unique<camera::ConicProfile>(0, 1 / kApexRadius, -1, 0.001, rim_rho), pose,
          width, height};
}

// An equiangular mirror before a webcam of some 50 degrees across (fx = width / 2 / tan 25 deg),
// seeing from 50 degrees below the horizon to 50 above: the rim ray, leaving the camera at
// theta_rim = atan(R / fx), must leave the mirror 140 degrees from -z, so alpha = 140 deg /
// theta_rim. r0 = 7.6 cm, a mirror of a few centimetres.
camera::CatadioptricCamera equiangular_start(const MirrorImage& mirror, int width, int height) {
  camera::PinholeIntrinsics lens;
  lens.fx = lens.fy = width / 2.0 / std::tan(25 * kDegree);
  lens.cx = mirror.centre.x();
  lens.cy = mirror.centre.y();
  const double theta_rim = std::atan(mirror.outer_radius / lens.fx);
  const double alpha = 140 * kDegree / theta_rim;
  // The rim a little beyond the picture's edge, inside the profile's domain pi / (1 + alpha).
  const double theta_max = std::min(1.1 * theta_rim, 0.95 * M_PI / (1 + alpha));
  const double theta_min = 0.8 * std::atan(mirror.inner_radius / lens.fx);
  return {std::make_unique<camera::PinholeCamera>(lens),
          std::make_unique<camera::EquiangularProfile>(alpha, 0.076, theta_min, theta_max),
          camera::MirrorPose{}, width, height};
}

}  // namespace

camera::CatadioptricCamera starting_camera(const MirrorImage& mirror, int image_width,
                                           int image_height, StartingMirror mirror_kind,
                                           StartingInner inner_kind) {
  if (!(mirror.outer_radius > mirror.inner_radius && mirror.inner_radius >= 0))
    throw std::invalid_argument("the camera's reflection must lie inside the "
                                "mirror's picture");
  if (mirror_kind == StartingMirror::kEquiangular) {
    if (inner_kind == StartingInner::kOrthographic)
      throw std::invalid_argument("no generic start for an equiangular mirror "
                                  "before a telecentric lens; write one");
    return equiangular_start(mirror, image_width, image_height);
  }
  return inner_kind == StartingInner::kPinhole
             ? hyperbolic_start(mirror, image_width, image_height)
             : parabolic_start(mirror, image_width, image_height);
}

}  // namespace omnisfm::calib
