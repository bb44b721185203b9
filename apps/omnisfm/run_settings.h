#pragma once
// `omnisfm run --config run.ini`: the estimators' [sfm] section (sfm/settings_file.h) and a [run]
// section for the replay, whose keys OmniSfmEstimator shares (mrpt_plugin/run_options.h); absent
// keys keep their defaults. Other sections are errors (a misspelt [sfm] would otherwise be
// silently ignored).

#include <string>

#include "omnisfm/mrpt_plugin/run_options.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::app {

struct RunSettings : mrpt_plugin::RunOptions {
  sfm::SfmSettings sfm;
};

// Defaults for an empty path. Throws io::InputError naming the file, the key and its line.
RunSettings read_run_settings(const std::string& path);

}  // namespace omnisfm::app
