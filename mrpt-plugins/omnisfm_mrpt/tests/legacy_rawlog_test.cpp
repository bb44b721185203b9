// Rawlogs outlive class versions: data/version0.rawlog was written by the first version (0) of
// every class of the plugin, and is kept as it is. Every later version must read it into the same
// objects. It holds an omnidirectional image and tracked features whose camera models cover every
// inner camera (pinhole, orthographic, mrcal) and every mirror (equiangular, conic, table).
//
// The file is never rewritten. A class's next version adds data/version1.rawlog beside it, written
// by setting OMNISFM_WRITE_LEGACY_RAWLOG to the new file's path and running
// LegacyRawlog.WriteReference, after changing reference_objects() to what the new version stores.

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>

#include <cstdlib>

#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"
#include "test_cameras.h"

namespace omnisfm::mrpt_plugin {
namespace {

mrpt::obs::CObservation::Ptr omni_image() {
  auto obs = CObservationOmniImage::Create();
  obs->timestamp = mrpt::Clock::fromDouble(1e9 + 0.5);
  obs->sensorLabel = "OMNI_CAMERA";
  obs->cameraPose = mrpt::poses::CPose3D(0.01, -0.02, 0.6, 0.1, 0.0, M_PI);
  obs->set_camera(sim::default_rig(64, 48));
  obs->image = mrpt::img::CImage(64, 48, mrpt::img::CH_GRAY);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) obs->image.at<uint8_t>(x, y) = static_cast<uint8_t>(4 * x + y);
  return obs;
}

mrpt::obs::CObservation::Ptr features(int frame, const std::string& camera_name) {
  auto obs = CObservationTrackedFeatures::Create();
  obs->timestamp = mrpt::Clock::fromDouble(1e9 + 0.5 * frame);
  obs->sensorLabel = "OMNI_TRACKS";
  obs->frame = frame;
  obs->sensorPose = mrpt::poses::CPose3D(0, 0, 0.6, 0, 0, 0);
  for (const auto& named : camera::testing::contract_cameras())
    if (named.name == camera_name) obs->model.set_camera(named.make());
  for (int track = 0; track < 5; ++track)
    obs->features.push_back({track * 7 + frame, 100.0 + track / 3.0, 200.0 - frame / 7.0});
  return obs;
}

std::vector<mrpt::obs::CObservation::Ptr> reference_objects() {
  return {omni_image(), features(0, "ParabolicOrthographicMisaligned"),
          features(1, "EquiangularMrcalOpencv8"), features(2, "TablePinhole"), features(3, "")};
}

void expect_same_model(const CCatadioptricCameraModel& a, const CCatadioptricCameraModel& b) {
  ASSERT_EQ(a.has_camera(), b.has_camera());
  if (!a.has_camera()) return;
  EXPECT_EQ(a.camera().inner().kind(), b.camera().inner().kind());
  EXPECT_EQ(a.camera().mirror().kind(), b.camera().mirror().kind());
  EXPECT_EQ(a.camera().params(), b.camera().params());
  EXPECT_EQ(a.camera().mirror().s_max(), b.camera().mirror().s_max());
  EXPECT_EQ(a.camera().image_width(), b.camera().image_width());
}

void expect_same(const mrpt::obs::CObservation& expected, const mrpt::obs::CObservation& read) {
  EXPECT_STREQ(read.GetRuntimeClass()->className, expected.GetRuntimeClass()->className);
  EXPECT_EQ(read.timestamp, expected.timestamp);
  EXPECT_EQ(read.sensorLabel, expected.sensorLabel);
  if (const auto* image = dynamic_cast<const CObservationOmniImage*>(&expected)) {
    const auto& got = dynamic_cast<const CObservationOmniImage&>(read);
    EXPECT_EQ(got.cameraPose, image->cameraPose);
    EXPECT_EQ(got.cameraParams.ncols, image->cameraParams.ncols);
    EXPECT_EQ(got.cameraParams.fx(), image->cameraParams.fx());
    ASSERT_EQ(got.image.getWidth(), image->image.getWidth());
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x)
        ASSERT_EQ(got.image.at<uint8_t>(x, y), image->image.at<uint8_t>(x, y));
    expect_same_model(got.model, image->model);
  }
  if (const auto* tracked = dynamic_cast<const CObservationTrackedFeatures*>(&expected)) {
    const auto& got = dynamic_cast<const CObservationTrackedFeatures&>(read);
    EXPECT_EQ(got.frame, tracked->frame);
    EXPECT_EQ(got.sensorPose, tracked->sensorPose);
    ASSERT_EQ(got.features.size(), tracked->features.size());
    for (std::size_t i = 0; i < got.features.size(); ++i) {
      EXPECT_EQ(got.features[i].track, tracked->features[i].track);
      EXPECT_EQ(got.features[i].u, tracked->features[i].u);
      EXPECT_EQ(got.features[i].v, tracked->features[i].v);
    }
    expect_same_model(got.model, tracked->model);
  }
}

TEST(LegacyRawlog, Version0StillReads) {
  RawlogReader reader(std::string(OMNISFM_MRPT_TEST_DATA) + "/version0.rawlog");
  const auto expected = reference_objects();
  std::size_t count = 0;
  while (const auto object = reader.next()) {
    ASSERT_LT(count, expected.size());
    const auto observation = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object);
    ASSERT_TRUE(observation);
    SCOPED_TRACE("object " + std::to_string(count));
    expect_same(*expected[count], *observation);
    ++count;
  }
  EXPECT_TRUE(reader.problem().empty()) << reader.problem();
  EXPECT_EQ(count, expected.size());
}

TEST(LegacyRawlog, WriteReference) {
  const char* path = std::getenv("OMNISFM_WRITE_LEGACY_RAWLOG");
  if (!path)
    GTEST_SKIP() << "writes a reference rawlog only when OMNISFM_WRITE_LEGACY_RAWLOG is set";
  mrpt::io::CFileGZOutputStream file(path, mrpt::io::OpenMode::TRUNCATE, 9);
  auto archive = mrpt::serialization::archiveFrom(file);
  for (const auto& object : reference_objects()) archive << *object;
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
