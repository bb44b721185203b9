// Rawlogs written by earlier versions of the classes keep reading: data/version0.rawlog, written
// by the first versions, holds an omnidirectional image and tracked features whose camera models
// cover every inner camera (pinhole, orthographic, mrcal) and every mirror (equiangular, conic,
// table), and reads as legacy_rawlog_objects.h's reference objects. The file is never rewritten:
// a class's next version adds data/version1.rawlog beside it (write_legacy_rawlog).

#include <gtest/gtest.h>

#include "legacy_rawlog_objects.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

using testing::reference_objects;

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

void expect_reads_as_the_reference(const std::string& path) {
  RawlogReader reader(path);
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

TEST(LegacyRawlog, Version0StillReads) {
  expect_reads_as_the_reference(std::string(OMNISFM_MRPT_TEST_DATA) + "/version0.rawlog");
}

// What write_legacy_rawlog writes for the next version reads back as the reference objects.
TEST(LegacyRawlog, TheWriterWritesTheReference) {
  const std::string path = testing::temporary_path("reference.rawlog");
  testing::write_reference_rawlog(path);
  expect_reads_as_the_reference(path);
  EXPECT_THROW(testing::write_reference_rawlog("/nonexistent/folder/reference.rawlog"),
               std::exception);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
