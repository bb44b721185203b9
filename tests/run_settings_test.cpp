// The [run] settings of `omnisfm run --config`: the shipped example holds every key at its
// default, every key lands in its field, and a bad value names the file and the line.

#include "run_settings.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/input_error.h"

namespace omnisfm::app {
namespace {

std::string example_path() {
  const char* source = std::getenv("OMNISFM_SOURCE_DIR");
  return source ? std::string(source) + "/share/omnisfm/config/omnisfm.ini" : "";
}

// A settings file in a temporary folder of this process's own.
std::string written(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("omnisfm_run_settings_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(RunSettings, ShippedExampleHoldsEveryKeyAtItsDefault) {
  ASSERT_FALSE(example_path().empty()) << "ctest sets OMNISFM_SOURCE_DIR";
  const io::IniFile ini = io::IniFile::read(example_path());
  const io::IniSection& section = ini.section("run");
  for (const char* key :
       {"vision", "camera_label", "odometry_label", "gyro_label", "gps_label",
        "odometry_position_sigma", "odometry_heading_sigma", "odometry_scale",
        "odometry_scale_sigma", "gyro_noise_density", "gyro_bias_sigma", "gyro_bias_walk",
        "max_tracks", "min_ncc", "keyframe_distance_m", "keyframe_angle_deg"})
    EXPECT_TRUE(section.has(key)) << key;
  const RunSettings read = read_run_settings(example_path());
  const RunSettings defaults;
  EXPECT_EQ(read.replay.vision, defaults.replay.vision);
  EXPECT_EQ(read.replay.camera_label, defaults.replay.camera_label);
  EXPECT_EQ(read.replay.odometry_label, defaults.replay.odometry_label);
  EXPECT_EQ(read.replay.gyro_label, defaults.replay.gyro_label);
  EXPECT_EQ(read.replay.gps_label, defaults.replay.gps_label);
  EXPECT_FALSE(read.replay.gps_origin.has_value());
  EXPECT_EQ(read.odometry_noise.position_sigma, defaults.odometry_noise.position_sigma);
  EXPECT_EQ(read.odometry_noise.heading_sigma, defaults.odometry_noise.heading_sigma);
  EXPECT_EQ(read.odometry_noise.scale_sigma, defaults.odometry_noise.scale_sigma);
  EXPECT_EQ(read.odometry_scale, defaults.odometry_scale);
  EXPECT_EQ(read.gyro_noise.noise_density, defaults.gyro_noise.noise_density);
  EXPECT_EQ(read.gyro_noise.bias_sigma, defaults.gyro_noise.bias_sigma);
  EXPECT_EQ(read.gyro_noise.bias_walk, defaults.gyro_noise.bias_walk);
  EXPECT_EQ(read.replay.tracker.max_tracks, defaults.replay.tracker.max_tracks);
  EXPECT_EQ(read.replay.tracker.min_ncc, defaults.replay.tracker.min_ncc);
  EXPECT_EQ(read.sfm.filter.pixel_sigma, defaults.sfm.filter.pixel_sigma);
  EXPECT_EQ(read.keyframe_distance_m, defaults.keyframe_distance_m);
  EXPECT_NEAR(read.keyframe_angle_rad, defaults.keyframe_angle_rad, 1e-15);
}

TEST(RunSettings, EveryKeyLandsInItsField) {
  const RunSettings s = read_run_settings(written(
      "keys.ini",
      "[run]\nvision = images\ncamera_label = OMNI\nodometry_label = ODO\ngyro_label = IMU\n"
      "gps_label = GPS\ngps_origin = 40.5 -79.9 280\nodometry_position_sigma = 0.002\n"
      "odometry_heading_sigma = 0.003\nodometry_scale = 0.985\nodometry_scale_sigma = 0\n"
      "gyro_noise_density = 1e-4\ngyro_bias_sigma = 1e-3\ngyro_bias_walk = 1e-5\n"
      "max_tracks = 50\nmin_ncc = 0.9\n[sfm]\npixel_sigma = 0.2\n"));
  EXPECT_EQ(s.replay.vision, mrpt_plugin::ReplayVision::kImages);
  EXPECT_EQ(s.replay.camera_label, "OMNI");
  EXPECT_EQ(s.replay.odometry_label, "ODO");
  EXPECT_EQ(s.replay.gyro_label, "IMU");
  EXPECT_EQ(s.replay.gps_label, "GPS");
  ASSERT_TRUE(s.replay.gps_origin.has_value());
  EXPECT_EQ(s.replay.gps_origin->latitude_deg, 40.5);
  EXPECT_EQ(s.replay.gps_origin->longitude_deg, -79.9);
  EXPECT_EQ(s.replay.gps_origin->height_m, 280);
  EXPECT_EQ(s.odometry_noise.position_sigma, 0.002);
  EXPECT_EQ(s.odometry_noise.heading_sigma, 0.003);
  EXPECT_EQ(s.odometry_scale, 0.985);
  EXPECT_EQ(s.odometry_noise.scale_sigma, 0);
  EXPECT_EQ(s.gyro_noise.noise_density, 1e-4);
  EXPECT_EQ(s.gyro_noise.bias_sigma, 1e-3);
  EXPECT_EQ(s.gyro_noise.bias_walk, 1e-5);
  EXPECT_EQ(s.replay.tracker.max_tracks, 50);
  EXPECT_EQ(s.replay.tracker.min_ncc, 0.9);
  EXPECT_EQ(s.sfm.filter.pixel_sigma, 0.2);
}

TEST(RunSettings, BadValuesNameTheirLine) {
  const auto error_of = [](const std::string& name, const std::string& text) -> std::string {
    try {
      read_run_settings(written(name, text));
    } catch (const io::InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(error_of("scale.ini", "[run]\n\nodometry_scale = -1\n").find("scale.ini:3:"),
            std::string::npos);
  EXPECT_NE(error_of("vision.ini", "[run]\nvision = video\n").find("vision.ini:2:"),
            std::string::npos);
  EXPECT_NE(error_of("origin.ini", "[run]\ngps_origin = 95 0 0\n").find("origin.ini:2:"),
            std::string::npos);
  EXPECT_NE(error_of("ncc.ini", "[run]\nmin_ncc = 1.5\n").find("ncc.ini:2:"), std::string::npos);
}

// Sensor noises that are numerically zero or say nothing (each ran far off or failed away from
// the file: a gyro bias sigma of 1e308 ended in exit 1, an odometry scale of 1e-300 200 % off) are
// refused at their line with the range; the ends of each range are taken.
TEST(RunSettings, SensorSettingsBeyondWhatTheyCanMeanAreRefused) {
  const auto error_of = [](const std::string& text) -> std::string {
    try {
      read_run_settings(written("sensor.ini", "[run]\n" + text + "\n"));
    } catch (const io::InputError& e) {
      return e.what();
    }
    return "";
  };
  for (const char* bad :
       {"odometry_position_sigma = 1e-300", "odometry_position_sigma = 1e308",
        "odometry_heading_sigma = 2", "odometry_scale = 1e-300", "odometry_scale = 1000",
        "odometry_scale_sigma = 10", "gyro_noise_density = 1e308", "gyro_bias_sigma = 1e-300",
        "gyro_bias_sigma = 1e308", "gyro_bias_walk = 1e308", "gyro_bias_walk = 0"}) {
    const std::string message = error_of(bad);
    const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_NE(message.find("sensor.ini:2: key '" + key + "': must be from "), std::string::npos)
        << bad << ": " << message;
  }
  for (const char* good :
       {"odometry_position_sigma = 1e-6", "odometry_position_sigma = 1", "odometry_scale = 0.1",
        "odometry_scale = 10", "odometry_scale_sigma = 0", "odometry_scale_sigma = 0.5",
        "gyro_noise_density = 1e-7", "gyro_bias_walk = 1"})
    EXPECT_EQ(error_of(good), "") << good;
}

}  // namespace
}  // namespace omnisfm::app
