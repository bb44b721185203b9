// The [sfm] settings: every key lands in its field, and a bad value or an unknown key fails
// naming the file and the line.

#include "omnisfm/sfm/settings_file.h"

#include <gtest/gtest.h>

#include <sstream>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/input_error.h"

namespace omnisfm::sfm {
namespace {

SfmSettings settings_of(const std::string& text) {
  std::istringstream in(text);
  return read_sfm_settings(io::IniFile::parse(in, "test.ini").section("sfm"));
}

// The message of the error reading `text` throws, or "" when it reads.
std::string error_of(const std::string& text) {
  try {
    settings_of(text);
  } catch (const io::InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SfmSettings, EveryKeyLandsInItsField) {
  const SfmSettings s = settings_of(
      "[sfm]\npixel_sigma = 0.5\nupdate_iterations = 3\nsmoothed_start_frames = 0\n"
      "batch = 1\nbatch_outlier_threshold_px = 3\nhuber_px = 1.5\ncovariances = 0\n"
      "max_iterations = 50\nbatch_scale_start = 0\n");
  EXPECT_EQ(s.filter.pixel_sigma, 0.5);
  EXPECT_EQ(s.filter.update_iterations, 3);
  EXPECT_EQ(s.filter.smoothed_start_frames, 0);
  EXPECT_TRUE(s.run_batch);
  EXPECT_EQ(s.batch_outlier_threshold_px, 3);
  EXPECT_EQ(s.batch.huber_px, 1.5);
  EXPECT_FALSE(s.batch.covariances);
  EXPECT_EQ(s.batch.max_iterations, 50);
  EXPECT_FALSE(s.batch.scale_start);
  // Absent keys keep the defaults.
  const SfmSettings defaults = settings_of("[sfm]\n");
  EXPECT_TRUE(defaults.batch.scale_start);
  EXPECT_EQ(defaults.batch.max_iterations, BatchSettings{}.max_iterations);
}

TEST(SfmSettings, BadValuesAndUnknownKeysNameTheirLine) {
  EXPECT_NE(error_of("[sfm]\nbatch_scale_start = 2\n").find("test.ini:2:"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\n\nmax_iterations = 2.5\n").find("test.ini:3:"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\nupdate_iterations = 0\n").find("test.ini:2:"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\nbatch_scale = 1\n").find("unknown key"), std::string::npos);
}

}  // namespace
}  // namespace omnisfm::sfm
