// A simulated dataset as a rawlog: the tracks exactly, the images, the odometry and gyro of the
// sensor models, in time order, and the sensors' true errors in the leading comment.

#include "omnisfm/mrpt_plugin/simulated_rawlog.h"

#include <gtest/gtest.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "omnisfm/io/number_text.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_input.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

sim::Dataset dataset_of(const std::string& scenario) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  return sim::simulate(options);
}

struct Contents {
  std::vector<mrpt::serialization::CSerializable::Ptr> objects;
  std::string problem;
  template <typename T>
  std::vector<std::shared_ptr<T>> all() const {
    std::vector<std::shared_ptr<T>> found;
    for (const auto& object : objects)
      if (auto typed = std::dynamic_pointer_cast<T>(object)) found.push_back(typed);
    return found;
  }
};

Contents read_all(const std::string& path) {
  RawlogReader reader(path);
  Contents contents;
  while (auto object = reader.next()) contents.objects.push_back(object);
  contents.problem = reader.problem();
  return contents;
}

TEST(SimulatedRawlog, HoldsTheLabAsStated) {
  const sim::Dataset lab = dataset_of("lab");
  const std::string path = testing::temporary_path("lab.rawlog");
  const SimulatedRawlogOptions options;
  const SimulatedRawlogSummary summary = write_simulated_rawlog(lab, path, options);
  EXPECT_EQ(summary.images, 0u);
  EXPECT_EQ(summary.tracked_frames, 41u);
  EXPECT_EQ(summary.odometry, 401u);  // 40 s at 10 Hz
  EXPECT_EQ(summary.gyro, 4001u);     // at 100 Hz

  const Contents contents = read_all(path);
  EXPECT_TRUE(contents.problem.empty()) << contents.problem;
  ASSERT_EQ(contents.objects.size(), 1 + 41 + 401 + 4001u);

  // In time order, the comment first.
  const auto comment =
      std::dynamic_pointer_cast<mrpt::obs::CObservationComment>(contents.objects[0]);
  ASSERT_TRUE(comment);
  EXPECT_NE(comment->text.find("libomnisfm_mrpt_classes.so"), std::string::npos);
  EXPECT_NE(comment->text.find("odometry_scale_error = 0.015"), std::string::npos) << comment->text;
  double previous = 0;
  for (const auto& object : contents.objects) {
    const double t = mrpt::Clock::toDouble(
        std::dynamic_pointer_cast<mrpt::obs::CObservation>(object)->timestamp);
    EXPECT_GE(t, previous);
    previous = t;
  }
  EXPECT_DOUBLE_EQ(previous, options.start_time + lab.timestamps.back());

  // The odometry and the gyro are the sensor models' readings, with the same seed.
  const sim::DeadReckoning truth = sim::simulate_dead_reckoning(lab, options.sensors);
  const auto odometry = contents.all<mrpt::obs::CObservationOdometry>();
  ASSERT_EQ(odometry.size(), truth.odometry.size());
  EXPECT_EQ(odometry.back()->sensorLabel, kOdometryLabel);
  // To 1e-12: MRPT wraps the heading itself, compiled apart from the simulation's sums.
  EXPECT_NEAR(odometry.back()->odometry.x(), truth.odometry.back().pose.x(), 1e-12);
  EXPECT_NEAR(odometry.back()->odometry.phi(), truth.odometry.back().pose.z(), 1e-12);
  const auto gyro = contents.all<mrpt::obs::CObservationIMU>();
  ASSERT_EQ(gyro.size(), truth.gyro.size());
  EXPECT_EQ(gyro[100]->get(mrpt::obs::IMU_WZ), truth.gyro[100].rate.z());
  EXPECT_FALSE(gyro[100]->has(mrpt::obs::IMU_X_ACC)) << "a gyro only";
  EXPECT_NE(
      comment->text.find("gyro_bias_at_start = " + io::format_double(truth.gyro_bias_at_start.x())),
      std::string::npos);

  // The cameras sit on the robot upside down: the lab's rig hangs from the bench.
  const auto frames = contents.all<CObservationTrackedFeatures>();
  ASSERT_EQ(frames.size(), 41u);
  EXPECT_NEAR(frames[0]->sensorPose.roll(), M_PI, 1e-12);
}

TEST(SimulatedRawlog, TracksComeBackExactly) {
  const sim::Dataset rover = dataset_of("rover");
  const std::string path = testing::temporary_path("rover.rawlog");
  write_simulated_rawlog(rover, path, SimulatedRawlogOptions{});
  RawlogTracks tracks;
  const RawlogReadResult result = read_rawlog_tracks(path, &tracks);
  EXPECT_TRUE(result.complete()) << result.problem;
  ASSERT_EQ(tracks.observations.size(), rover.observations.size());
  for (std::size_t i = 0; i < rover.observations.size(); ++i) {
    EXPECT_EQ(tracks.observations[i].frame, rover.observations[i].frame);
    EXPECT_EQ(tracks.observations[i].track, rover.observations[i].track);
    EXPECT_EQ(tracks.observations[i].pixel, rover.observations[i].pixel);
  }
  ASSERT_EQ(tracks.frames.size(), rover.timestamps.size());
  EXPECT_DOUBLE_EQ(tracks.frames[7].timestamp, 1e9 + rover.timestamps[7]);
  ASSERT_TRUE(tracks.camera);
  EXPECT_EQ(tracks.camera->params(), rover.camera.params());
}

TEST(SimulatedRawlog, CraneHasNoWheelOdometry) {
  const std::string path = testing::temporary_path("crane.rawlog");
  const SimulatedRawlogSummary summary =
      write_simulated_rawlog(dataset_of("crane"), path, SimulatedRawlogOptions{});
  EXPECT_EQ(summary.odometry, 0u);
  EXPECT_GT(summary.gyro, 0u);
  const Contents contents = read_all(path);
  EXPECT_TRUE(contents.all<mrpt::obs::CObservationOdometry>().empty());
  const auto comment =
      std::dynamic_pointer_cast<mrpt::obs::CObservationComment>(contents.objects[0]);
  ASSERT_TRUE(comment);
  EXPECT_NE(comment->text.find("odometry = none"), std::string::npos);
}

TEST(SimulatedRawlog, CarriesTheImages) {
  const sim::Dataset lab = dataset_of("lab");
  cv::Mat picture(lab.camera.image_height(), lab.camera.image_width(), CV_8UC1);
  for (int y = 0; y < picture.rows; ++y)
    for (int x = 0; x < picture.cols; ++x) picture.at<uint8_t>(y, x) = static_cast<uint8_t>(x ^ y);
  const std::string png = testing::temporary_path("frame.png");
  ASSERT_TRUE(cv::imwrite(png, picture));

  SimulatedRawlogOptions options;
  options.image_file = [&](int) { return png; };
  const std::string path = testing::temporary_path("lab_images.rawlog");
  EXPECT_EQ(write_simulated_rawlog(lab, path, options).images, 41u);

  std::size_t images = 0;
  const RawlogReadResult result = for_each_rawlog_image(path, [&](RawlogImage& image) {
    EXPECT_EQ(image.sensor_label, kOmniCameraLabel);
    EXPECT_DOUBLE_EQ(image.timestamp, options.start_time + lab.timestamps[images]);
    ASSERT_TRUE(image.camera);
    EXPECT_EQ(cv::norm(image.grey, picture, cv::NORM_INF), 0);
    ++images;
  });
  EXPECT_TRUE(result.complete()) << result.problem;
  EXPECT_EQ(images, 41u);
}

TEST(SimulatedRawlog, UnreadableImageLeavesNoRawlog) {
  SimulatedRawlogOptions options;
  options.image_file = [](int frame) {
    return testing::temporary_path("missing_" + std::to_string(frame) + ".png");
  };
  const std::string path = testing::temporary_path("no_images.rawlog");
  std::filesystem::remove(path);
  try {
    write_simulated_rawlog(dataset_of("lab"), path, options);
    FAIL() << "a missing image was not reported";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("missing_0.png: cannot read the image of frame 0"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
