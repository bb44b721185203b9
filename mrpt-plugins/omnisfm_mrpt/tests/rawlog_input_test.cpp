// Images and tracks out of rawlogs: omnisfm's omnidirectional images with their camera, stock
// camera images (also inside sensory frames), tracked features; damage stops the reading at the
// object it is in.

#include "omnisfm/mrpt_plugin/rawlog_input.h"

#include <gtest/gtest.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <filesystem>

#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

mrpt::img::CImage colour_image(int width, int height) {
  mrpt::img::CImage image(width, height, mrpt::img::CH_RGB);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int channel = 0; channel < 3; ++channel)
        image.at<uint8_t>(x, y, channel) = static_cast<uint8_t>(x + 10 * y + 50 * channel);
  return image;
}

mrpt::img::CImage grey_image(int width, int height, int seed) {
  mrpt::img::CImage image(width, height, mrpt::img::CH_GRAY);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image.at<uint8_t>(x, y) = static_cast<uint8_t>(seed + x * y);
  return image;
}

class ImageRawlog : public ::testing::Test {
 protected:
  void SetUp() override {
    stock_.timestamp = mrpt::Clock::fromDouble(1e9 + 1);
    stock_.sensorLabel = "CAMERA";
    stock_.image = colour_image(32, 24);
    stock_.cameraPose = mrpt::poses::CPose3D(0.5, 0, 1, 0, 0, 0);

    omni_.timestamp = mrpt::Clock::fromDouble(1e9 + 2);
    omni_.sensorLabel = "OMNI_CAMERA";
    omni_.image = grey_image(64, 48, 7);
    omni_.set_camera(sim::default_rig(64, 48));

    // The actions-and-sensory-frames format: an image inside a frame, after an action.
    auto in_frame = mrpt::obs::CObservationImage::Create();
    in_frame->timestamp = mrpt::Clock::fromDouble(1e9 + 3);
    in_frame->sensorLabel = "CAMERA";
    in_frame->image = grey_image(32, 24, 99);
    frame_.insert(in_frame);

    features_.timestamp = mrpt::Clock::fromDouble(1e9 + 2);
    features_.sensorLabel = "OMNI_TRACKS";
    features_.frame = 5;
    features_.features = {{11, 1.5, 2.5}, {12, 3.5, 4.5}};
    features_.model.set_camera(sim::default_rig(64, 48));

    testing::write_plain_rawlog(path_, {&stock_, &omni_, &features_, &actions_, &frame_});
  }

  const std::string path_ = testing::temporary_path("images.rawlog");
  mrpt::obs::CObservationImage stock_;
  CObservationOmniImage omni_;
  CObservationTrackedFeatures features_;
  mrpt::obs::CActionCollection actions_;
  mrpt::obs::CSensoryFrame frame_;
};

TEST_F(ImageRawlog, GivesEveryImageInGrey) {
  std::vector<RawlogImage> images;
  const RawlogReadResult result =
      for_each_rawlog_image(path_, [&](RawlogImage& image) { images.push_back(image); });
  EXPECT_TRUE(result.complete()) << result.problem;
  EXPECT_EQ(result.objects, 5u);
  EXPECT_EQ(result.used, 3u);
  ASSERT_EQ(images.size(), 3u);

  EXPECT_EQ(images[0].object_index, 0u);
  EXPECT_EQ(images[0].sensor_label, "CAMERA");
  EXPECT_DOUBLE_EQ(images[0].timestamp, 1e9 + 1);
  EXPECT_FALSE(images[0].camera) << "a stock image's camera comes from a camera file";
  EXPECT_TRUE(images[0].robot_from_cam.translation().isApprox(Eigen::Vector3d(0.5, 0, 1)));
  ASSERT_EQ(images[0].grey.type(), CV_8UC1);
  EXPECT_EQ(images[0].grey.cols, 32);
  EXPECT_EQ(images[0].grey.rows, 24);

  EXPECT_EQ(images[1].object_index, 1u);
  ASSERT_TRUE(images[1].camera);
  EXPECT_EQ(images[1].camera->params(), sim::default_rig(64, 48).params());
  EXPECT_EQ(images[1].grey.at<uint8_t>(5, 9), static_cast<uint8_t>(7 + 9 * 5));

  EXPECT_EQ(images[2].object_index, 4u);
  EXPECT_DOUBLE_EQ(images[2].timestamp, 1e9 + 3);
  EXPECT_EQ(images[2].grey.at<uint8_t>(3, 4), static_cast<uint8_t>(99 + 12));
}

TEST_F(ImageRawlog, OneSensorOnly) {
  std::vector<std::size_t> indices;
  const RawlogReadResult result = for_each_rawlog_image(
      path_, [&](RawlogImage& image) { indices.push_back(image.object_index); }, "CAMERA");
  EXPECT_EQ(indices, (std::vector<std::size_t>{0, 4}));
  EXPECT_EQ(result.used, 2u);
}

TEST_F(ImageRawlog, GivesTheTracks) {
  RawlogTracks tracks;
  const RawlogReadResult result = read_rawlog_tracks(path_, &tracks);
  EXPECT_TRUE(result.complete()) << result.problem;
  EXPECT_EQ(result.used, 1u);
  ASSERT_EQ(tracks.observations.size(), 2u);
  EXPECT_EQ(tracks.observations[1].frame, 5);
  EXPECT_EQ(tracks.observations[1].track, 12);
  EXPECT_EQ(tracks.observations[1].pixel, Eigen::Vector2d(3.5, 4.5));
  ASSERT_EQ(tracks.frames.size(), 1u);
  EXPECT_EQ(tracks.frames[0].frame, 5);
  EXPECT_DOUBLE_EQ(tracks.frames[0].timestamp, 1e9 + 2);
  ASSERT_TRUE(tracks.camera);
}

TEST_F(ImageRawlog, TruncatedKeepsTheImagesBefore) {
  const testing::Bytes bytes = testing::read_file(path_);
  const std::string cut = testing::temporary_path("images_cut.rawlog");
  testing::write_file(cut, testing::Bytes(bytes.begin(), bytes.end() - 100));
  std::size_t seen = 0;
  const RawlogReadResult result = for_each_rawlog_image(cut, [&](RawlogImage&) { ++seen; });
  EXPECT_EQ(seen, 2u);
  EXPECT_EQ(result.objects, 4u);
  EXPECT_NE(result.problem.find("object 4 (mrpt::obs::CSensoryFrame): the file ends inside it"),
            std::string::npos)
      << result.problem;
}

TEST(RawlogInput, ExternalImagesBesideTheRawlog) {
  // As rawlog-grabber stores them: images in <rawlog name>_Images, named in the observations.
  const std::string path = testing::temporary_path("grabbed.rawlog");
  const std::string folder = testing::temporary_path("grabbed_Images");
  std::filesystem::create_directories(folder);
  ASSERT_TRUE(grey_image(40, 30, 3).saveToFile(folder + "/img_0001.png"));
  mrpt::obs::CObservationImage external;
  external.sensorLabel = "CAMERA";
  external.image.setExternalStorage("img_0001.png");
  testing::write_plain_rawlog(path, {&external});
  std::vector<cv::Mat> images;
  const RawlogReadResult result =
      for_each_rawlog_image(path, [&](RawlogImage& image) { images.push_back(image.grey); });
  EXPECT_TRUE(result.complete()) << result.problem;
  ASSERT_EQ(images.size(), 1u);
  EXPECT_EQ(images[0].cols, 40);
  EXPECT_EQ(images[0].at<uint8_t>(2, 7), static_cast<uint8_t>(3 + 14));
}

TEST(RawlogInput, MissingExternalImageIsDamageAtItsObject) {
  mrpt::obs::CObservationImage present, external;
  present.image = grey_image(8, 8, 1);
  external.image.setExternalStorage("no_such_image.png");
  const std::string path = testing::temporary_path("external.rawlog");
  testing::write_plain_rawlog(path, {&present, &external, &present});
  std::size_t seen = 0;
  const RawlogReadResult result = for_each_rawlog_image(path, [&](RawlogImage&) { ++seen; });
  EXPECT_EQ(seen, 1u);
  EXPECT_EQ(result.objects, 1u);
  EXPECT_NE(result.problem.find("object 1 (mrpt::obs::CObservationImage): its image cannot be "
                                "loaded: Error loading externally-stored image from: "),
            std::string::npos)
      << result.problem;
  EXPECT_EQ(result.problem.find("Call stack"), std::string::npos) << result.problem;
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
