// The observations through MRPT serialization, as MRPT's own code sees them: an omnidirectional
// image is a CObservationImage with its image, pose and lens, plus the catadioptric model; tracked
// features keep every id and pixel.

#include <gtest/gtest.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/rtti/CObject.h>

#include <sstream>

#include "omnisfm/mrpt_plugin/image_camera_models.h"
#include "omnisfm/mrpt_plugin/observation_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/register_classes.h"
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

CObservationCameraModel camera_model(const std::string& label) {
  CObservationCameraModel obs;
  obs.timestamp = mrpt::Clock::fromDouble(1e9 + 1);
  obs.sensorLabel = label;
  obs.sensorPose = mrpt::poses::CPose3D(0.1, 0.2, 0.3, 0.4, 0.5, 0.6);
  obs.model.set_camera(sim::default_rig(64, 48));
  return obs;
}

TEST(ObservationCameraModel, KeepsTheModelAndThePose) {
  const CObservationCameraModel original = camera_model("OMNI_CAMERA");
  const auto read = testing::round_trip<CObservationCameraModel>(original);
  ASSERT_TRUE(read);
  EXPECT_EQ(read->timestamp, original.timestamp);
  EXPECT_EQ(read->sensorLabel, "OMNI_CAMERA");
  EXPECT_EQ(read->sensorPose, original.sensorPose);
  ASSERT_TRUE(read->model.has_camera());
  EXPECT_EQ(read->model.camera().params(), original.model.camera().params());
  std::ostringstream text;
  read->getDescriptionAsText(text);
  EXPECT_NE(text.str().find("Camera model (omnisfm) of the stock CObservationImage observations "
                            "labelled 'OMNI_CAMERA'"),
            std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("Catadioptric camera model: pinhole camera, equiangular mirror"),
            std::string::npos);
  testing::Bytes bytes = testing::to_bytes(original);
  bytes[testing::version_byte(bytes, "omnisfm::mrpt_plugin::CObservationCameraModel")] = 1;
  EXPECT_THROW(testing::from_bytes(bytes), std::exception);
}

// A stock image takes the last model seen under its label; an omnisfm image keeps its own.
TEST(ImageCameraModels, GiveAStockImageTheLastModelOfItsLabel) {
  ImageCameraModels models;
  mrpt::obs::CObservationImage stock;
  stock.sensorLabel = "OMNI_CAMERA";
  EXPECT_EQ(models.model_for(stock), nullptr);
  EXPECT_FALSE(models.note(stock));
  EXPECT_TRUE(models.note(camera_model("OTHER")));
  EXPECT_EQ(models.model_for(stock), nullptr);
  CObservationCameraModel first = camera_model("OMNI_CAMERA");
  EXPECT_TRUE(models.note(first));
  ASSERT_NE(models.model_for(stock), nullptr);
  EXPECT_EQ(models.model_for(stock)->camera().params(), first.model.camera().params());
  CObservationCameraModel second = camera_model("OMNI_CAMERA");
  second.model.set_camera(sim::default_rig(128, 96));
  models.note(second);
  EXPECT_EQ(models.model_for(stock)->camera().image_width(), 128);
  const CObservationOmniImage omni = omni_image();
  ASSERT_NE(models.model_for(omni), nullptr);
  EXPECT_EQ(models.model_for(omni)->camera().image_width(), 64);
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
  EXPECT_EQ(read->model.camera().mirror().kind(), camera::MirrorKind::kConic);
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

TEST(ObservationTrackedFeatures, ExportRowHoldsEveryFeatureExactly) {
  const CObservationTrackedFeatures obs = tracked_features();
  EXPECT_TRUE(obs.exportTxtSupported());
  EXPECT_EQ(obs.exportTxtDataRow(), "8 3 3 100.25 200.5 17 -0.5 0.125 4000000 1023.5 767.5");
  EXPECT_EQ(obs.exportTxtHeader().find('\n'), std::string::npos);
  EXPECT_EQ(obs.exportTxtDataRow().find('\n'), std::string::npos);
}

TEST(ObservationTrackedFeatures, VisualisedRaysProjectToTheirPixels) {
  const camera::CatadioptricCamera camera = camera::testing::hyperbolic_camera();
  CObservationTrackedFeatures obs = tracked_features();
  obs.model.set_camera(camera);
  obs.features.clear();
  size_t unprojectable = 0;
  for (int i = 0; i < 24; ++i) {
    const double a = 0.5 * i, r = 60 + 15 * i;  // some inside the mirror's ring, some beyond
    const Eigen::Vector2d pixel(512 + r * std::cos(a), 384 + r * std::sin(a));
    Eigen::Vector3d origin, direction;
    unprojectable += camera.unproject(pixel, &origin, &direction);
    obs.features.push_back({i, pixel.x(), pixel.y()});
  }
  ASSERT_GE(unprojectable, 8u);
  mrpt::opengl::CSetOfObjects scene;
  obs.getVisualizationInto(scene);
  const auto rays = scene.getByClass<mrpt::opengl::CSetOfLines>();
  ASSERT_TRUE(rays);
  ASSERT_EQ(rays->getLineCount(), unprojectable);
  size_t line = 0;
  for (const TrackedFeature& feature : obs.features) {
    Eigen::Vector3d origin, direction;
    if (!camera.unproject({feature.u, feature.v}, &origin, &direction)) continue;
    double x0, y0, z0, x1, y1, z1;
    rays->getLineByIndex(line++, x0, y0, z0, x1, y1, z1);
    const mrpt::math::TPoint3D start = obs.sensorPose.inverseComposePoint({x0, y0, z0});
    const mrpt::math::TPoint3D end = obs.sensorPose.inverseComposePoint({x1, y1, z1});
    const Eigen::Vector3d from(start.x, start.y, start.z), to(end.x, end.y, end.z);
    EXPECT_NEAR((to - from).norm(), CObservationTrackedFeatures::kVisualizedRayLength, 1e-9);
    // Any point along the ray is seen at the feature's pixel (rays are in the robot frame).
    const Eigen::Vector3d middle = from + 0.5 * (to - from);
    for (const Eigen::Vector3d& X : {to, middle}) {
      Eigen::Vector2d pixel;
      ASSERT_TRUE(camera.project(X, &pixel)) << feature.track;
      EXPECT_NEAR(pixel.x(), feature.u, 1e-6) << feature.track;
      EXPECT_NEAR(pixel.y(), feature.v, 1e-6) << feature.track;
    }
  }
}

TEST(ObservationTrackedFeatures, NoModelNoRays) {
  mrpt::opengl::CSetOfObjects scene;
  tracked_features().getVisualizationInto(scene);
  EXPECT_EQ(scene.size(), 0u);
}

TEST(Registry, RegisteringAgainAsMrptModulesAllowIsHarmless) {
  registerAllClasses_omnisfm_mrpt();
  const mrpt::rtti::TRuntimeClassId* id =
      mrpt::rtti::findRegisteredClass("omnisfm::mrpt_plugin::CObservationTrackedFeatures");
  ASSERT_NE(id, nullptr);
  EXPECT_TRUE(id->createObject());
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
