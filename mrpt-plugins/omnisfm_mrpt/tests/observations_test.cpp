// The observations through MRPT serialization, as MRPT's own code sees them: an omnidirectional
// image is a CObservationImage with its image, pose and lens, plus the catadioptric model; tracked
// features keep every id and pixel.

#include <gtest/gtest.h>
#include <mrpt/rtti/CObject.h>

#include <sstream>

#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"
#include "test_cameras.h"

namespace omnisfm::mrpt_plugin {
namespace {

mrpt::img::CImage gradient_image(int width, int height) {
  mrpt::img::CImage image(width, height, mrpt::img::CH_GRAY);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.at<uint8_t>(x, y) = static_cast<uint8_t>((3 * x + 5 * y) % 256);
  return image;
}

CObservationOmniImage omni_image() {
  CObservationOmniImage obs;
  obs.timestamp = mrpt::Clock::fromDouble(1e9 + 2.5);
  obs.sensorLabel = "OMNI_CAMERA";
  obs.cameraPose = mrpt::poses::CPose3D(0.1, 0.2, 0.3, 0.4, 0.5, 0.6);
  obs.set_camera(sim::default_rig(64, 48));
  obs.image = gradient_image(64, 48);
  return obs;
}

TEST(ObservationOmniImage, IsAStockCameraImageToMrpt) {
  const CObservationOmniImage original = omni_image();
  const auto read = testing::round_trip<mrpt::obs::CObservation>(original);
  ASSERT_TRUE(read);
  EXPECT_TRUE(IS_DERIVED(*read, mrpt::obs::CObservationImage));
  EXPECT_STREQ(read->GetRuntimeClass()->className, "omnisfm::mrpt_plugin::CObservationOmniImage");

  const auto& image = dynamic_cast<const mrpt::obs::CObservationImage&>(*read);
  EXPECT_EQ(image.timestamp, original.timestamp);
  EXPECT_EQ(image.sensorLabel, "OMNI_CAMERA");
  EXPECT_EQ(image.cameraPose, original.cameraPose);
  ASSERT_EQ(image.image.getWidth(), 64u);
  ASSERT_EQ(image.image.getHeight(), 48u);
  for (int y = 0; y < 48; y += 7)
    for (int x = 0; x < 64; x += 5)
      EXPECT_EQ(image.image.at<uint8_t>(x, y), original.image.at<uint8_t>(x, y));
  // The lens: the default rig's pinhole, 200 px at 64 px wide, centred.
  EXPECT_EQ(image.cameraParams.ncols, 64u);
  EXPECT_DOUBLE_EQ(image.cameraParams.fx(), 800 * 64 / 1024.0);
  EXPECT_DOUBLE_EQ(image.cameraParams.cx(), 31.5);

  const auto& omni = dynamic_cast<const CObservationOmniImage&>(*read);
  ASSERT_TRUE(omni.model.has_camera());
  EXPECT_EQ(omni.model.camera().params(), original.model.camera().params());
}

TEST(ObservationOmniImage, OtherInnerCamerasGiveOnlyTheImageSize) {
  const mrpt::img::TCamera lens = inner_camera_params(camera::testing::parabolic_camera());
  EXPECT_EQ(lens.ncols, 1024u);
  EXPECT_EQ(lens.nrows, 768u);
  EXPECT_EQ(lens.distortion, mrpt::img::DistortionModel::none);
  EXPECT_EQ(lens.cameraName, "omnisfm orthographic inner camera");
}

TEST(ObservationOmniImage, DescriptionShowsImageAndModel) {
  std::ostringstream text;
  omni_image().getDescriptionAsText(text);
  EXPECT_NE(text.str().find("Image size: 64x48"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("Catadioptric camera model: pinhole camera, equiangular mirror"),
            std::string::npos)
      << text.str();
}

TEST(ObservationOmniImage, RefusesAVersionItDoesNotKnow) {
  testing::Bytes bytes = testing::to_bytes(omni_image());
  bytes[testing::version_byte(bytes, "omnisfm::mrpt_plugin::CObservationOmniImage")] = 1;
  EXPECT_THROW(testing::from_bytes(bytes), std::exception);
}

CObservationTrackedFeatures tracked_features() {
  CObservationTrackedFeatures obs;
  obs.timestamp = mrpt::Clock::fromDouble(1e9 + 4);
  obs.sensorLabel = "OMNI_TRACKS";
  obs.frame = 8;
  obs.sensorPose = mrpt::poses::CPose3D(0, 0, 0.6, 0, 0, M_PI);
  obs.features = {{3, 100.25, 200.5}, {17, -0.5, 0.125}, {4000000, 1023.5, 767.5}};
  return obs;
}

TEST(ObservationTrackedFeatures, KeepsEveryIdAndPixel) {
  CObservationTrackedFeatures original = tracked_features();
  original.model.set_camera(camera::testing::hyperbolic_camera());
  const auto read = testing::round_trip<CObservationTrackedFeatures>(original);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->timestamp, original.timestamp);
  EXPECT_EQ(read->sensorLabel, "OMNI_TRACKS");
  EXPECT_EQ(read->frame, 8);
  EXPECT_EQ(read->sensorPose, original.sensorPose);
  ASSERT_EQ(read->features.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(read->features[i].track, original.features[i].track);
    EXPECT_EQ(read->features[i].u, original.features[i].u);
    EXPECT_EQ(read->features[i].v, original.features[i].v);
  }
  ASSERT_TRUE(read->model.has_camera());
  EXPECT_EQ(read->model.camera().mirror().kind(), "conic");
}

TEST(ObservationTrackedFeatures, WithoutAModel) {
  const auto read = testing::round_trip<CObservationTrackedFeatures>(tracked_features());
  ASSERT_TRUE(read);
  EXPECT_FALSE(read->model.has_camera());
  EXPECT_EQ(read->features.size(), 3u);
}

TEST(ObservationTrackedFeatures, DescriptionListsTheFeatures) {
  std::ostringstream text;
  tracked_features().getDescriptionAsText(text);
  EXPECT_NE(text.str().find("Tracked features (omnisfm): frame 8, 3 features"), std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("17 -0.5 0.125\n"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("Sensor label: 'OMNI_TRACKS'"), std::string::npos) << text.str();
}

TEST(Registry, KnowsThePluginsClasses) {
  for (const char* name : {"omnisfm::mrpt_plugin::CCatadioptricCameraModel",
                           "omnisfm::mrpt_plugin::CObservationOmniImage",
                           "omnisfm::mrpt_plugin::CObservationTrackedFeatures"}) {
    const mrpt::rtti::TRuntimeClassId* id = mrpt::rtti::findRegisteredClass(name);
    ASSERT_NE(id, nullptr) << name;
    EXPECT_TRUE(id->createObject()) << name;
  }
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
