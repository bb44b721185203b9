// Which parameters a calibration holds because the others make them unobservable.

#include "omnisfm/calib/parameter_gauge.h"

#include <gtest/gtest.h>

#include <memory>

#include "omnisfm/calib/calibration_problem.h"
#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/orthographic_camera.h"
#include "omnisfm/camera/pinhole_camera.h"

namespace omnisfm::calib {
namespace {

camera::CatadioptricCamera conic_on(std::unique_ptr<camera::InnerCamera> inner) {
  return camera::CatadioptricCamera(
      std::move(inner), std::make_unique<camera::ConicProfile>(0, 50, -1, 0.001, 0.03),
      camera::MirrorPose{0, 0, 0, 0, 0.1}, 1024, 768);
}

std::unique_ptr<camera::InnerCamera> pinhole() {
  return std::make_unique<camera::PinholeCamera>(camera::PinholeIntrinsics{800, 800, 512, 384});
}

std::unique_ptr<camera::InnerCamera> telecentric() {
  return std::make_unique<camera::OrthographicCamera>(
      camera::OrthographicIntrinsics{12500, 12500, 512, 384});
}

std::vector<std::string> held_names(const camera::CatadioptricCamera& camera,
                                    const std::vector<std::string>& groups,
                                    std::vector<bool>* mask = nullptr) {
  std::vector<bool> estimate = estimate_mask(camera, groups);
  std::vector<std::string> names;
  for (const HeldParameter& held : hold_unobservable_parameters(camera, &estimate)) {
    EXPECT_FALSE(held.reason.empty());
    names.push_back(held.name);
  }
  if (mask) *mask = estimate;
  return names;
}

TEST(ParameterGauge, ThePapersMethodHoldsNothing) {
  EXPECT_TRUE(held_names(conic_on(pinhole()), {"mirror-pose"}).empty());
  const camera::CatadioptricCamera equiangular(
      pinhole(), std::make_unique<camera::EquiangularProfile>(5, 0.05, 0.02, 0.35), {}, 1024, 768);
  EXPECT_TRUE(held_names(equiangular, {"mirror-pose"}).empty());
  EXPECT_EQ(held_names(equiangular, {"all"}), (std::vector<std::string>{"equiangular_r0"}));
}

TEST(ParameterGauge, CentralCameraHoldsTheConicsOffsetAndSize) {
  std::vector<bool> mask;
  const camera::CatadioptricCamera camera = conic_on(pinhole());
  EXPECT_EQ(held_names(camera, {"all"}, &mask),
            (std::vector<std::string>{"conic_z0", "conic_c"}));
  const auto names = camera.param_names();
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(mask[i], names[i] != "conic_z0" && names[i] != "conic_c") << names[i];
  }
  // Without the mirror's translation, its shape is observable in full.
  EXPECT_TRUE(held_names(camera, {"mirror-shape", "intrinsics"}).empty());
}

TEST(ParameterGauge, TelecentricCameraHoldsWhatItCannotSee) {
  const camera::CatadioptricCamera camera = conic_on(telecentric());
  EXPECT_EQ(held_names(camera, {"mirror-pose"}), (std::vector<std::string>{"mirror_tz"}));
  EXPECT_EQ(held_names(camera, {"mirror-pose", "intrinsics", "mirror-shape"}),
            (std::vector<std::string>{"conic_z0", "conic_c", "mirror_tx", "mirror_ty",
                                      "mirror_tz"}));
  // Focal lengths fixed: the mirror's size is what sets the scale, and it is observable.
  EXPECT_EQ(held_names(camera, {"mirror-shape"}), (std::vector<std::string>{"conic_z0"}));
}

}  // namespace
}  // namespace omnisfm::calib
