// The [sfm] settings: every key lands in its field, a bad value or an unknown key fails naming
// the file and the line, and the shipped example holds every key at its default; settings and
// sensors set in code meet the same ranges.

#include "omnisfm/sfm/settings_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sfm/sensor_ranges.h"
#include "omnisfm/sfm/settings_ranges.h"
#include "omnisfm/sim/scenario.h"

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
      "max_iterations = 50\nbatch_scale_start = 0\nknown_distance_m = 4.08\n"
      "refine_camera = 1\nconsider_camera = 1\nbatch_track_false_alarm = 0.001\n"
      "max_live_points = 40\nthreads = 1\nlinearise_at_constant_velocity = 1\n");
  EXPECT_EQ(s.filter.pixel_sigma, 0.5);
  EXPECT_TRUE(s.filter.linearise_at_constant_velocity);
  EXPECT_EQ(s.filter.max_live_points, 40);
  EXPECT_EQ(s.batch.threads, 1);
  EXPECT_EQ(s.batch_track_false_alarm, 0.001);
  EXPECT_EQ(s.filter.update_iterations, 3);
  EXPECT_EQ(s.filter.smoothed_start_frames, 0);
  EXPECT_TRUE(s.run_batch);
  EXPECT_EQ(s.batch_outlier_threshold_px, 3);
  EXPECT_EQ(s.batch.huber_px, 1.5);
  EXPECT_FALSE(s.batch.covariances);
  EXPECT_EQ(s.batch.max_iterations, 50);
  EXPECT_FALSE(s.batch.scale_start);
  EXPECT_EQ(s.batch.known_distance_m, 4.08);
  EXPECT_TRUE(s.refine_camera);
  EXPECT_TRUE(s.consider_camera);
  // Absent keys keep the defaults; an empty known distance is not known.
  const SfmSettings defaults = settings_of("[sfm]\n");
  EXPECT_TRUE(defaults.batch.scale_start);
  EXPECT_EQ(defaults.batch.known_distance_m, 0);
  EXPECT_EQ(settings_of("[sfm]\nknown_distance_m =   # not known\n").batch.known_distance_m, 0);
  EXPECT_EQ(defaults.batch.max_iterations, BatchSettings{}.max_iterations);
}

// The chi-square test by default, its limit in pixels sqrt(outlier_chi2) pixel_sigmas; the
// paper's rule on request, with its own limits.
TEST(SfmSettings, OutlierTestsAndTheirLimits) {
  const SfmSettings chi2 = settings_of("[sfm]\npixel_sigma = 0.5\noutlier_chi2 = 16\n");
  EXPECT_EQ(chi2.filter.outlier_test, OutlierTest::kChiSquare);
  EXPECT_DOUBLE_EQ(chi2.filter.residual_limit_px(), 2.0);
  EXPECT_DOUBLE_EQ(chi2.batch_residual_limit_px(), 2.0);
  const SfmSettings pixels = settings_of(
      "[sfm]\noutlier_test = pixels\noutlier_threshold_px = 1.5\nbatch_outlier_threshold_px = 3\n");
  EXPECT_EQ(pixels.filter.outlier_test, OutlierTest::kPixels);
  EXPECT_EQ(pixels.filter.residual_limit_px(), 1.5);
  EXPECT_EQ(pixels.batch_residual_limit_px(), 3);
  EXPECT_EQ(settings_of("[sfm]\nbatch_outliers = false\n").batch_residual_limit_px(), 0);
  const std::string bad = error_of("[sfm]\n\noutlier_test = sigma\n");
  EXPECT_EQ(bad.rfind("test.ini:3:", 0), 0u) << bad;
  EXPECT_NE(bad.find("chi2"), std::string::npos) << bad;
  EXPECT_EQ(error_of("[sfm]\noutlier_chi2 = 0\n").rfind("test.ini:2:", 0), 0u);
}

TEST(SfmSettings, BadValuesAndUnknownKeysNameTheirLine) {
  EXPECT_NE(error_of("[sfm]\nbatch_scale_start = 2\n").find("test.ini:2:"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\n\nmax_iterations = 2.5\n").find("test.ini:3:"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\nupdate_iterations = 0\n").find("test.ini:2:"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\nbatch_scale = 1\n").find("unknown key"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\nbatch_track_false_alarm = 1\n").find("test.ini:2:"),
            std::string::npos);
  EXPECT_NE(error_of("[sfm]\nbatch_track_false_alarm = -0.1\n").find("test.ini:2:"),
            std::string::npos);
  EXPECT_EQ(settings_of("[sfm]\nbatch_track_false_alarm = 0\n").batch_track_false_alarm, 0);
  EXPECT_NE(error_of("[sfm]\nmax_live_points = 5\n")
                .find("test.ini:2: key 'max_live_points': "
                      "must be from 6 to 1000: the filter starts from 6 points"),
            std::string::npos)
      << error_of("[sfm]\nmax_live_points = 5\n");
}

// Settings that make the problem meaningless: a noise of 0 (every residual infinitely sure), a
// known distance of 0, below 0 or infinite.
TEST(SfmSettings, MeaninglessNoiseAndDistancesAreRefusedAtTheirLine) {
  for (const char* bad : {"pixel_sigma = 0", "pixel_sigma = -0.2", "pixel_sigma = inf",
                          "known_distance_m = 0", "known_distance_m = -4", "known_distance_m = inf",
                          "known_distance_m = nan", "known_distance_m = 1e400",
                          "known_distance_m = four"}) {
    const std::string message = error_of("[sfm]\nbatch = 1\n" + std::string(bad) + "\n");
    EXPECT_EQ(message.rfind("test.ini:3:", 0), 0u) << bad << ": " << message;
    const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_NE(message.find("'" + key + "'"), std::string::npos) << message;
  }
  EXPECT_NE(error_of("[sfm]\nknown_distance_m = 0\n").find("empty when not known"),
            std::string::npos);
  // The camera is refined in the batch: without one there is nothing to refine it in.
  const std::string no_batch = error_of("[sfm]\nbatch = 0\nrefine_camera = 1\n");
  EXPECT_EQ(no_batch.rfind("test.ini:3:", 0), 0u) << no_batch;
  EXPECT_NE(no_batch.find("batch = false"), std::string::npos) << no_batch;
}

// Values within their type but beyond what they can mean (probed: each ended in exit 1 blaming the
// camera's motion, or in a result far off with exit 0, or an infinite trajectory) are refused at
// their line with the range; the ends of each range are taken.
TEST(SfmSettings, SettingsBeyondWhatTheyCanMeanAreRefusedAtTheirLine) {
  for (const char* bad :
       {"pixel_sigma = 1e-300", "pixel_sigma = 1e308", "rotation_walk_sigma = 1e308",
        "translation_walk_sigma = 0", "translation_walk_sigma = 1e308", "initial_depth = 1e-300",
        "initial_depth = 1e308", "inverse_depth_sigma = 1e308", "outlier_chi2 = 1",
        "innovation_gate_chi2 = 1e-300", "outlier_threshold_px = 1e-300", "huber_px = 1e-300",
        "batch_outlier_threshold_px = 1e-300", "update_iterations = 1000000",
        "max_iterations = 2000000000", "max_live_points = 100000", "known_distance_m = 1e308",
        "known_distance_m = 1e-300"}) {
    const std::string message = error_of("[sfm]\n" + std::string(bad) + "\n");
    const std::string key = std::string(bad).substr(0, std::string(bad).find(' '));
    EXPECT_EQ(message.rfind("test.ini:2: key '" + key + "': must be ", 0), 0u)
        << bad << ": " << message;
  }
  EXPECT_NE(error_of("[sfm]\noutlier_chi2 = 1\n").find("at least 5.99"), std::string::npos);
  EXPECT_NE(error_of("[sfm]\npixel_sigma = 1e-300\n").find("from 0.001 to 100"), std::string::npos);
  for (const char* good :
       {"pixel_sigma = 0.001", "pixel_sigma = 100", "rotation_walk_sigma = 0",
        "translation_walk_sigma = 1e-6", "outlier_chi2 = 5.99", "outlier_chi2 = 1e308",
        "innovation_gate_chi2 = 0", "huber_px = 0", "known_distance_m = 0.001",
        "known_distance_m = 1e8", "max_live_points = 1000", "update_iterations = 100"})
    EXPECT_EQ(error_of("[sfm]\n" + std::string(good) + "\n"), "") << good;
}

// Every row of a range table: both ends taken by `problem`; just below, beyond (infinity where
// unbounded) and NaN named by it, each such setting then handed to `refused` for the caller's
// own checks.
template <typename Row, typename Settings, typename Problem, typename Refused>
void expect_rows_judged(const std::vector<Row>& rows, const Settings& base, Problem problem,
                        Refused refused) {
  for (const Row& r : rows) {
    for (const double value : {r.low, r.high}) {
      Settings ends = base;
      r.field(ends) = value;
      EXPECT_EQ(problem(ends), "") << r.key << " = " << value;
    }
    const double below = r.low > 0 ? r.low / 2 : -1;
    const double beyond = r.high < std::numeric_limits<double>::max() ? 2 * r.high : INFINITY;
    for (const double value : {below, beyond, std::numeric_limits<double>::quiet_NaN()}) {
      Settings bad = base;
      r.field(bad) = value;
      const std::string wrong = problem(bad);
      EXPECT_EQ(wrong.rfind(std::string(r.key) + " = ", 0), 0u) << r.key << ": " << wrong;
      EXPECT_NE(wrong.find(" must be "), std::string::npos) << wrong;
      refused(r, bad, value);
    }
  }
}

// Settings set in code meet the same ranges (settings_ranges.h): each number just beyond its
// range, NaN, and each count beyond its own is refused by the filter and the pipeline, naming the
// setting; the ends of each range and the defaults are taken.
TEST(SfmSettings, SettingsSetInCodeMeetTheFilesRanges) {
  EXPECT_EQ(settings_problem(SfmSettings()), "");
  const camera::CatadioptricCamera camera = sim::default_rig(256, 192);
  int filter_refusals = 0;
  expect_rows_judged(
      setting_ranges(), SfmSettings(), [](const SfmSettings& s) { return settings_problem(s); },
      [&](const SettingRange& r, const SfmSettings& bad, double value) {
        EXPECT_THROW(run_sfm(camera, {}, bad), std::invalid_argument) << r.key << " = " << value;
        if (!settings_problem(bad.filter).empty()) {  // the filter's own
          ++filter_refusals;
          EXPECT_THROW(OnlineFilter(camera, bad.filter), std::invalid_argument) << r.key;
        }
      });
  EXPECT_EQ(filter_refusals, 8 * 3);  // the filter's eight numbers, each three ways
  SfmSettings bad;
  bad.filter.pixel_sigma = 0;
  EXPECT_EQ(settings_problem(bad),
            "pixel_sigma = 0 must be from 0.001 to 100: pixels per coordinate (no tracker is surer "
            "than a thousandth of a pixel; beyond 100 the pixels say nothing)");
  const auto problem_with = [](auto change) {
    SfmSettings s;
    change(s);
    return settings_problem(s);
  };
  EXPECT_EQ(problem_with([](SfmSettings& s) { s.filter.update_iterations = 0; }),
            "update_iterations = 0 must be from 1 to 100");
  EXPECT_EQ(problem_with([](SfmSettings& s) { s.filter.max_live_points = 5; }),
            "max_live_points = 5 must be from 6 to 1000: the filter starts from 6 points, and "
            "1,000 take 290 MB of covariance");
  EXPECT_EQ(problem_with([](SfmSettings& s) {
              s.filter.smoothed_start_frames = 1;
            }).rfind("smoothed_start_frames = 1 must be at least 2 (or 0: off)", 0),
            0u);
  EXPECT_NE(problem_with([](SfmSettings& s) { s.batch.max_iterations = 0; }), "");
  EXPECT_EQ(problem_with([](SfmSettings& s) { s.filter.smoothed_start_frames = 0; }), "");
}

// The motion sensors' numbers set in code meet the [run] section's ranges: both ends taken, just
// beyond and NaN refused, by the check and by run_fused_sfm.
TEST(SensorSettings, SensorsSetInCodeMeetTheRunSectionsRanges) {
  EXPECT_EQ(sensors_problem(MotionSensors()), "");
  const camera::CatadioptricCamera camera = sim::default_rig(256, 192);
  MotionSensors with_a_wheel;
  with_a_wheel.odometry.resize(1);
  expect_rows_judged(
      sensor_ranges(), with_a_wheel, [](const MotionSensors& s) { return sensors_problem(s); },
      [&](const SensorRange& r, const MotionSensors& bad, double value) {
        try {
          run_fused_sfm(camera, {}, {}, bad, SfmSettings());
          ADD_FAILURE() << r.key << " = " << value << " was taken";
        } catch (const std::invalid_argument& e) {  // before the tracks, which are none
          EXPECT_EQ(std::string(e.what()).rfind("MotionSensors: " + std::string(r.key), 0), 0u)
              << e.what();
        }
      });
  EXPECT_EQ(sensor_ranges().size(), 7u);  // the odometry's four numbers and the gyro's three
  MotionSensors bad;
  bad.odometry_scale = 20;
  EXPECT_EQ(sensors_problem(bad),
            "odometry_scale = 20 must be from 0.1 to 10: true distance per distance read (a factor "
            "of ten off is another unit than MRPT's metres)");
}

// A setting the file does not put in [sfm] would be silently ignored: a key before any section
// and a section of another name are refused at their line; [run], the run verb's, is left to it
// (the shipped omnisfm.ini holds both).
TEST(SfmSettings, SettingsOutsideTheSfmSectionAreRefused) {
  const std::string path =
      testing::TempDir() + "/omnisfm-settings-" + std::to_string(::getpid()) + ".ini";
  const auto error_in = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      read_sfm_settings(path);
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_in("pixel_sigma = 1\n[sfm]\nbatch = 0\n"),
            path + ":1: key 'pixel_sigma': belongs in the [sfm] section");
  EXPECT_EQ(error_in("[sfm]\nbatch = 0\n[sfn]\npixel_sigma = 1\n"),
            path + ":3: unknown section [sfn]: expected [sfm] (or [run])");
  EXPECT_EQ(error_in("# comment\n[sfm]\nbatch = 0\n[run]\nodometry_label = ODO\n"), "");
  std::ofstream(path) << "[run]\nodometry_label = ODO\n[sfm]\npixel_sigma = 0.7\n";
  EXPECT_EQ(read_sfm_settings(path).filter.pixel_sigma, 0.7);
  std::remove(path.c_str());
}

TEST(SfmSettings, CameraPriorFromTheCalibrationsCovariance) {
  const camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  io::ParameterCovariance covariance;
  covariance.parameters = {"mirror_tz", "fx"};
  covariance.matrix = Eigen::Matrix2d(Eigen::Vector2d(1e-8, 0.25).asDiagonal());
  const CameraPrior prior = camera_prior_from(camera, covariance);
  const std::vector<std::string> names = camera.param_names();
  ASSERT_EQ(prior.parameters.size(), 2u);
  EXPECT_EQ(names[prior.parameters[0]], "mirror_tz");
  EXPECT_EQ(names[prior.parameters[1]], "fx");
  EXPECT_EQ(prior.covariance, covariance.matrix);
  covariance.parameters[1] = "focal";
  EXPECT_THROW(camera_prior_from(camera, covariance), std::invalid_argument);
}

// share/omnisfm/config/omnisfm.ini shows users every key at its default.
TEST(SfmSettings, ShippedExampleHoldsEveryKeyAtItsDefault) {
  const char* source = std::getenv("OMNISFM_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "ctest sets OMNISFM_SOURCE_DIR";
  const io::IniFile ini =
      io::IniFile::read(std::string(source) + "/share/omnisfm/config/omnisfm.ini");
  const io::IniSection& section = ini.section("sfm");
  for (const char* key : {"pixel_sigma",
                          "rotation_walk_sigma",
                          "translation_walk_sigma",
                          "initial_depth",
                          "inverse_depth_sigma",
                          "outlier_test",
                          "outlier_chi2",
                          "outlier_threshold_px",
                          "innovation_gate_chi2",
                          "update_iterations",
                          "linearise_at_constant_velocity",
                          "smoothed_start_frames",
                          "smoothing_window_frames",
                          "max_live_points",
                          "batch",
                          "batch_outliers",
                          "batch_outlier_threshold_px",
                          "batch_track_false_alarm",
                          "huber_px",
                          "covariances",
                          "max_iterations",
                          "batch_scale_start",
                          "known_distance_m",
                          "refine_camera",
                          "consider_camera",
                          "threads"})
    EXPECT_TRUE(section.has(key)) << key;
  const SfmSettings read = read_sfm_settings(section);
  const SfmSettings defaults;
  const FilterSettings& f = read.filter;
  EXPECT_EQ(f.pixel_sigma, defaults.filter.pixel_sigma);
  EXPECT_EQ(f.rotation_walk_sigma, defaults.filter.rotation_walk_sigma);
  EXPECT_EQ(f.translation_walk_sigma, defaults.filter.translation_walk_sigma);
  EXPECT_EQ(f.initial_depth, defaults.filter.initial_depth);
  EXPECT_EQ(f.inverse_depth_sigma, defaults.filter.inverse_depth_sigma);
  EXPECT_EQ(f.outlier_test, defaults.filter.outlier_test);
  EXPECT_EQ(f.outlier_chi2, defaults.filter.outlier_chi2);
  EXPECT_EQ(f.outlier_threshold_px, defaults.filter.outlier_threshold_px);
  EXPECT_EQ(f.innovation_gate_chi2, defaults.filter.innovation_gate_chi2);
  EXPECT_EQ(f.update_iterations, defaults.filter.update_iterations);
  EXPECT_EQ(f.linearise_at_constant_velocity, defaults.filter.linearise_at_constant_velocity);
  EXPECT_EQ(f.smoothed_start_frames, defaults.filter.smoothed_start_frames);
  EXPECT_EQ(f.smoothing_window_frames, defaults.filter.smoothing_window_frames);
  EXPECT_EQ(f.max_live_points, defaults.filter.max_live_points);
  EXPECT_EQ(read.run_batch, defaults.run_batch);
  EXPECT_EQ(read.batch_outliers, defaults.batch_outliers);
  EXPECT_EQ(read.batch_outlier_threshold_px, defaults.batch_outlier_threshold_px);
  EXPECT_EQ(read.batch_track_false_alarm, defaults.batch_track_false_alarm);
  EXPECT_EQ(read.batch.huber_px, defaults.batch.huber_px);
  EXPECT_EQ(read.batch.covariances, defaults.batch.covariances);
  EXPECT_EQ(read.batch.max_iterations, defaults.batch.max_iterations);
  EXPECT_EQ(read.refine_camera, defaults.refine_camera);
  EXPECT_EQ(read.consider_camera, defaults.consider_camera);
  EXPECT_EQ(read.batch.scale_start, defaults.batch.scale_start);
  EXPECT_EQ(read.batch.known_distance_m, defaults.batch.known_distance_m);
  EXPECT_EQ(read.batch.threads, defaults.batch.threads);
}

}  // namespace
}  // namespace omnisfm::sfm
