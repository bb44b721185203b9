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

// The same for a count, with its requirement's words ("from 1 to 100", "at least 2 (or 0: off)").
struct CountRange {
  const char* key;
  int low, high;  // a high of the largest int asks only for at least low
  bool zero_off;
  const char* meaning;  // "" where the range says it all
  int& (*field)(SfmSettings&);
  std::string requirement() const;  // "must be ...[: meaning]"
};

// The numbers with a range, the filter's first, and the counts.
const std::vector<SettingRange>& setting_ranges();
const std::vector<CountRange>& count_ranges();

// "" when every setting is within what it can mean, else the first that is not: "KEY = VALUE
// must be ...: MEANING".
std::string settings_problem(const SfmSettings& settings);
std::string settings_problem(const FilterSettings& settings);

}  // namespace omnisfm::sfm
