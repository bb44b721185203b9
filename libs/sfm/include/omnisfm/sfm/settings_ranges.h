#pragma once
// What each number of the shape-from-motion settings can mean: its [sfm] key, its range and why
// values beyond say nothing (a noise numerically zero, a walk that allows any pose, a covariance
// of gigabytes). One table for the settings file's reader (read_sfm_settings), which fails at the
// key's line, and for settings set in code (settings_problem), which OnlineFilter, run_sfm and
// run_fused_sfm refuse.

#include <string>
#include <vector>

#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::sfm {

struct SettingRange {
  const char* key;   // the [sfm] key, named as the member
  double low, high;  // a high of the largest double asks only for a finite number from low
  const char* meaning;
  bool zero_off;  // 0 is allowed too, and turns the setting off
  double& (*field)(SfmSettings&);
};

// The numbers with a range, the filter's first; the counts (update_iterations, max_live_points,
// smoothed_start_frames, max_iterations) are judged by settings_problem and the reader alike.
const std::vector<SettingRange>& setting_ranges();

// "" when every setting is within what it can mean, else the first that is not: "KEY = VALUE
// must be ...: MEANING".
std::string settings_problem(const SfmSettings& settings);
std::string settings_problem(const FilterSettings& settings);

}  // namespace omnisfm::sfm
