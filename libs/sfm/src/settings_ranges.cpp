#include "omnisfm/sfm/settings_ranges.h"

#include <limits>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::sfm {
namespace {

constexpr double kAnyFinite = std::numeric_limits<double>::max();
// Below chi-square's 95 % bound (2 dof) a good track, scored every frame, is rejected within a
// few dozen frames.
constexpr const char* kChi2Meaning =
    "a chi-square bound (2 degrees of freedom) of at least the 95 % one, 5.99";

}  // namespace

const std::vector<SettingRange>& setting_ranges() {
  static const std::vector<SettingRange> ranges = {
      {"pixel_sigma", 1e-3, 100,
       "pixels per coordinate (no tracker is surer than a thousandth of a pixel; beyond 100 the "
       "pixels say nothing)",
       false, [](SfmSettings& s) -> double& { return s.filter.pixel_sigma; }},
      {"rotation_walk_sigma", 0, 3.14,
       "radians per frame (0: the camera does not turn; a half turn is no walk)", false,
       [](SfmSettings& s) -> double& { return s.filter.rotation_walk_sigma; }},
      {"translation_walk_sigma", 1e-6, 1e6,
       "metres per frame (a camera that cannot move recovers no structure)", false,
       [](SfmSettings& s) -> double& { return s.filter.translation_walk_sigma; }},
      {"initial_depth", 1e-3, 1e6, "metres", false,
       [](SfmSettings& s) -> double& { return s.filter.initial_depth; }},
      {"inverse_depth_sigma", 1e-6, 1e6, "per metre", false,
       [](SfmSettings& s) -> double& { return s.filter.inverse_depth_sigma; }},
      {"outlier_chi2", 5.99, kAnyFinite, kChi2Meaning, false,
       [](SfmSettings& s) -> double& { return s.filter.outlier_chi2; }},
      {"outlier_threshold_px", 0.01, 1e6, "pixels", false,
       [](SfmSettings& s) -> double& { return s.filter.outlier_threshold_px; }},
      {"innovation_gate_chi2", 5.99, kAnyFinite, kChi2Meaning, true,
       [](SfmSettings& s) -> double& { return s.filter.innovation_gate_chi2; }},
      {"batch_outlier_threshold_px", 0.01, 1e6, "pixels", true,
       [](SfmSettings& s) -> double& { return s.batch_outlier_threshold_px; }},
      {"huber_px", 0.01, 1e6, "pixels", true,
       [](SfmSettings& s) -> double& { return s.batch.huber_px; }},
      // Below a millimetre or beyond 1e8 m (a thousand times the Earth) no rig's positions are.
      {"known_distance_m", 1e-3, 1e8,
       "the distance between the first and last camera positions in metres (0 when not known)",
       true, [](SfmSettings& s) -> double& { return s.batch.known_distance_m; }},
  };
  return ranges;
}

std::string CountRange::requirement() const {
  const std::string range = high < std::numeric_limits<int>::max()
                                ? "from " + std::to_string(low) + " to " + std::to_string(high)
                                : "at least " + std::to_string(low);
  return "must be " + range + (zero_off ? " (or 0: off)" : "") +
         (*meaning != '\0' ? std::string(": ") + meaning : std::string());
}

const std::vector<CountRange>& count_ranges() {
  static const std::vector<CountRange> ranges = {
      {"update_iterations", 1, 100, false, "",
       [](SfmSettings& s) -> int& { return s.filter.update_iterations; }},
      {"smoothed_start_frames", 2, std::numeric_limits<int>::max(), true, "",
       [](SfmSettings& s) -> int& { return s.filter.smoothed_start_frames; }},
      {"smoothing_window_frames", 0, std::numeric_limits<int>::max(), false, "",
       [](SfmSettings& s) -> int& { return s.filter.smoothing_window_frames; }},
      // The filter's covariance grows as the square of its points (6 columns each).
      {"max_live_points", 6, 1000, false,
       "the filter starts from 6 points, and 1,000 take 290 MB of covariance",
       [](SfmSettings& s) -> int& { return s.filter.max_live_points; }},
      {"max_iterations", 1, 1000000, false, "",
       [](SfmSettings& s) -> int& { return s.batch.max_iterations; }},
      // Ceres' threads sum the reduced system in whatever order they finish: on two, the rover's
      // batch positions differ between runs from their seventh digit on; on one, not at all.
      {"threads", 0, 1024, false, "the batch's threads (0: one per core)",
       [](SfmSettings& s) -> int& { return s.batch.threads; }},
  };
  return ranges;
}

std::string settings_problem(const SfmSettings& settings) {
  SfmSettings copy = settings;  // the fields are reached through the table's references
  for (const SettingRange& r : setting_ranges()) {
    const double value = r.field(copy);
    if (const std::string problem = io::range_problem(value, r.low, r.high, r.zero_off, r.meaning);
        !problem.empty())
      return std::string(r.key) + " = " + io::format_double(value) + " " + problem;
  }
  for (const CountRange& r : count_ranges()) {
    const int value = r.field(copy);
    if ((r.zero_off && value == 0) || (value >= r.low && value <= r.high)) continue;
    return std::string(r.key) + " = " + std::to_string(value) + " " + r.requirement();
  }
  // Not a file's key: the caller keeps the history.
  if (settings.filter.kept_history < 0)
    return "kept_history = " + std::to_string(settings.filter.kept_history) + " must be at least 0";
  return "";
}

std::string settings_problem(const FilterSettings& settings) {
  SfmSettings sfm;
  sfm.filter = settings;
  return settings_problem(sfm);
}

}  // namespace omnisfm::sfm
