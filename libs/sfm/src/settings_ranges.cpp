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

// A count from low to high (any from low where high is the largest int), or 0 with zero_off.
std::string count_problem(const char* key, int value, int low, int high, bool zero_off) {
  if ((zero_off && value == 0) || (value >= low && value <= high)) return "";
  const std::string range = high < std::numeric_limits<int>::max()
                                ? "from " + std::to_string(low) + " to " + std::to_string(high)
                                : "at least " + std::to_string(low);
  return std::string(key) + " = " + std::to_string(value) + " must be " + range +
         (zero_off ? " (or 0: off)" : "");
}

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

std::string settings_problem(const SfmSettings& settings) {
  SfmSettings copy = settings;  // the fields are reached through the table's references
  for (const SettingRange& r : setting_ranges()) {
    const double value = r.field(copy);
    if ((r.zero_off && value == 0) || (value >= r.low && value <= r.high)) continue;
    return std::string(r.key) + " = " + io::format_double(value) + " must be " +
           io::range_phrase(r.low, r.high, r.zero_off) + ": " + r.meaning;
  }
  const FilterSettings& f = settings.filter;
  for (const std::string& problem :
       {count_problem("update_iterations", f.update_iterations, 1, 100, false),
        // The filter's covariance grows as the square of its points (6 columns each): 1,000 take
        // 290 MB.
        count_problem("max_live_points", f.max_live_points, 6, 1000, false),
        count_problem("smoothed_start_frames", f.smoothed_start_frames, 2,
                      std::numeric_limits<int>::max(), true),
        count_problem("smoothing_window_frames", f.smoothing_window_frames, 0,
                      std::numeric_limits<int>::max(), false),
        count_problem("kept_history", f.kept_history, 0, std::numeric_limits<int>::max(), false),
        count_problem("max_iterations", settings.batch.max_iterations, 1, 1000000, false)})
    if (!problem.empty()) return problem;
  return "";
}

std::string settings_problem(const FilterSettings& settings) {
  SfmSettings sfm;
  sfm.filter = settings;
  return settings_problem(sfm);
}

}  // namespace omnisfm::sfm
