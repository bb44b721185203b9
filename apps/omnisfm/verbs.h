#pragma once
// Each verb adds its subcommand, options and callback to the `omnisfm` application.

#include <CLI/CLI.hpp>

namespace omnisfm::app {

void add_project_verb(CLI::App& app);
void add_unproject_verb(CLI::App& app);
void add_demo_verb(CLI::App& app);
void add_simulate_verb(CLI::App& app);
void add_sfm_verb(CLI::App& app);
void add_eval_verb(CLI::App& app);
void add_calibrate_verb(CLI::App& app);
void add_detect_corners_verb(CLI::App& app);
void add_export_mrcal_verb(CLI::App& app);
void add_track_verb(CLI::App& app);
// Only when omnisfm is built with the MRPT plugin (OMNISFM_WITH_MRPT_PLUGIN).
void add_run_verb(CLI::App& app);

}  // namespace omnisfm::app
