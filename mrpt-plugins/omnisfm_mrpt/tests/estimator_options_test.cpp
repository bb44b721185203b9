// OmniSfmEstimator's options as MRPT's loadable options: the shipped omnisfm.ini loads with the
// section `omnisfm run` reads, every key lands in its field, unknown keys are refused naming the
// file, and what is saved loads back.

#include <gtest/gtest.h>
#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "omnisfm/io/input_error.h"
#include "omnisfm/mrpt_plugin/omni_sfm_batch_estimator.h"
#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"

namespace omnisfm::mrpt_plugin {
namespace {

std::string shipped_ini() {
  const char* source = std::getenv("OMNISFM_SOURCE_DIR");
  return source ? std::string(source) + "/share/omnisfm/config/omnisfm.ini" : "";
}

std::string written(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("omnisfm_" + name + "_" + std::to_string(::getpid()) + ".ini");
  std::ofstream(path) << text;
  return path.string();
}

TEST(EstimatorOptions, TheShippedIniLoadsAtTheDefaults) {
  ASSERT_FALSE(shipped_ini().empty()) << "ctest sets OMNISFM_SOURCE_DIR";
  OmniSfmEstimatorOptions options;
  options.camera_label = "changed";
  options.keyframe_distance_m = 7;
  options.loadFromConfigFile(mrpt::config::CConfigFile(shipped_ini()), "run");
  const OmniSfmEstimatorOptions defaults;
  EXPECT_EQ(options.camera_label, defaults.camera_label);
  EXPECT_EQ(options.keyframe_distance_m, defaults.keyframe_distance_m);
  EXPECT_NEAR(options.keyframe_angle_rad, defaults.keyframe_angle_rad, 1e-15);
  EXPECT_EQ(options.odometry_noise.position_sigma, defaults.odometry_noise.position_sigma);
  EXPECT_EQ(options.gyro_noise.bias_walk, defaults.gyro_noise.bias_walk);
  EXPECT_EQ(options.tracker.max_tracks, defaults.tracker.max_tracks);
  EXPECT_EQ(options.filter.pixel_sigma, defaults.filter.pixel_sigma);
  EXPECT_EQ(options.filter.update_iterations, defaults.filter.update_iterations);
}

TEST(EstimatorOptions, EveryKeyLandsInItsField) {
  const std::string path = written("estimator", R"([sfm]
pixel_sigma = 0.7   # a comment
update_iterations = 3
[slam]
vision = images
camera_label = CAM
odometry_label = WHEELS
gyro_label = GYRO   // MRPT's comment
gps_label = FIX
gps_origin = 40.5 -79.9 280
odometry_position_sigma = 0.02
odometry_heading_sigma = 0.03
odometry_scale = 1.01
odometry_scale_sigma = 0
gyro_noise_density = 3e-4
gyro_bias_sigma = 0.004
gyro_bias_walk = 1e-5
max_tracks = 50
min_ncc = 0.9
keyframe_distance_m = 2.5
keyframe_angle_deg = 20
)");
  OmniSfmEstimatorOptions o;
  o.loadFromConfigFile(mrpt::config::CConfigFile(path), "slam");
  EXPECT_EQ(o.filter.pixel_sigma, 0.7);
  EXPECT_EQ(o.filter.update_iterations, 3);
  EXPECT_EQ(o.vision, ReplayVision::kImages);
  EXPECT_EQ(o.camera_label, "CAM");
  EXPECT_EQ(o.sensor_labels.odometry, "WHEELS");
  EXPECT_EQ(o.sensor_labels.gyro, "GYRO");
  EXPECT_EQ(o.sensor_labels.gps, "FIX");
  ASSERT_TRUE(o.gps_origin);
  EXPECT_EQ(o.gps_origin->latitude_deg, 40.5);
  EXPECT_EQ(o.gps_origin->height_m, 280);
  EXPECT_EQ(o.odometry_noise.position_sigma, 0.02);
  EXPECT_EQ(o.odometry_noise.heading_sigma, 0.03);
  EXPECT_EQ(o.odometry_scale, 1.01);
  EXPECT_EQ(o.odometry_noise.scale_sigma, 0);
  EXPECT_EQ(o.gyro_noise.noise_density, 3e-4);
  EXPECT_EQ(o.gyro_noise.bias_sigma, 0.004);
  EXPECT_EQ(o.gyro_noise.bias_walk, 1e-5);
  EXPECT_EQ(o.tracker.max_tracks, 50);
  EXPECT_EQ(o.tracker.min_ncc, 0.9);
  EXPECT_EQ(o.keyframe_distance_m, 2.5);
  EXPECT_NEAR(o.keyframe_angle_rad, 20 * M_PI / 180, 1e-15);

  // Saved and loaded back: the same options.
  mrpt::config::CConfigFileMemory memory;
  o.saveToConfigFile(memory, "slam");
  OmniSfmEstimatorOptions back;
  back.loadFromConfigFile(memory, "slam");
  EXPECT_EQ(back.vision, ReplayVision::kImages);
  EXPECT_EQ(back.camera_label, "CAM");
  EXPECT_EQ(back.sensor_labels.gps, "FIX");
  EXPECT_EQ(back.gps_origin->longitude_deg, -79.9);
  EXPECT_EQ(back.odometry_scale, 1.01);
  EXPECT_EQ(back.tracker.min_ncc, 0.9);
  EXPECT_NEAR(back.keyframe_angle_rad, o.keyframe_angle_rad, 1e-15);
  std::filesystem::remove(path);
}

TEST(EstimatorOptions, AKeyTheLoaderDoesNotKnowIsRefusedNamingTheFile) {
  const std::string path = written("unknown", "[slam]\ncamera_lable = CAM\n");
  OmniSfmEstimatorOptions o;
  try {
    o.loadFromConfigFile(mrpt::config::CConfigFile(path), "slam");
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("camera_lable"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("unknown key in [slam]"), std::string::npos) << e.what();
  }
  const std::string bad = written("bad", "[slam]\nodometry_scale = -1\n");
  EXPECT_THROW(o.loadFromConfigFile(mrpt::config::CConfigFile(bad), "slam"), io::InputError);
  // The tracker's settings, bounded as track's options are: refused here, not blamed on the
  // rawlog later.
  for (const char* tracker :
       {"[slam]\nmax_tracks = 1\n", "[slam]\nmax_tracks = 100000000\n", "[slam]\nmin_ncc = 1\n"}) {
    const std::string wrong = written("tracker", tracker);
    EXPECT_THROW(o.loadFromConfigFile(mrpt::config::CConfigFile(wrong), "slam"), io::InputError)
        << tracker;
    std::filesystem::remove(wrong);
  }
  // [sfm] consider_camera names a covariance the config cannot carry: refused, not ignored.
  const std::string consider = written("consider", "[slam]\n[sfm]\nconsider_camera = 1\n");
  try {
    o.loadFromConfigFile(mrpt::config::CConfigFile(consider), "slam");
    ADD_FAILURE() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("consider_camera"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("filter.camera_uncertainty"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
  std::filesystem::remove(bad);
  std::filesystem::remove(consider);
}

// Options set in code meet the settings file's ranges (sfm/settings_ranges.h), said when the
// estimator is made rather than at its first camera observation.
TEST(EstimatorOptions, FilterSettingsBeyondTheirRangeAreRefusedWhenTheEstimatorIsMade) {
  OmniSfmEstimatorOptions options;
  options.filter.pixel_sigma = 0;
  try {
    OmniSfmEstimator estimator(options);
    ADD_FAILURE() << "a pixel noise of 0 was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("OmniSfmEstimatorOptions::filter: pixel_sigma = 0 must "
                                          "be from 0.001 to 100",
                                          0),
              0u)
        << e.what();
  }
  options.filter.pixel_sigma = 0.3;
  EXPECT_NO_THROW(OmniSfmEstimator{options});
}

// The sensors' noises set in code meet the [run] section's ranges (sfm/sensor_ranges.h) too, and
// the batch estimator refuses what the online one does.
TEST(EstimatorOptions, SensorNoisesBeyondTheirRangeAreRefusedWhenTheEstimatorIsMade) {
  OmniSfmEstimatorOptions options;
  options.odometry_scale = 0;
  try {
    OmniSfmEstimator estimator(options);
    ADD_FAILURE() << "a wheel reading no distance was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind(
                  "OmniSfmEstimatorOptions: odometry_scale = 0 must be from 0.1 to 10", 0),
              0u)
        << e.what();
  }
  options.odometry_scale = 1;
  options.gyro_noise.bias_walk = -1;
  EXPECT_THROW(OmniSfmEstimator{options}, std::invalid_argument);
  EXPECT_THROW(OmniSfmBatchEstimator{options}, std::invalid_argument);
  options.gyro_noise.bias_walk = 2e-5;
  EXPECT_NO_THROW(OmniSfmEstimator{options});
  EXPECT_NO_THROW(OmniSfmBatchEstimator{options});
  options.filter.pixel_sigma = -1;
  EXPECT_THROW(OmniSfmBatchEstimator{options}, std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
