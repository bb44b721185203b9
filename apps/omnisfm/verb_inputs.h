#pragma once
// Inputs that several verbs take the same way.

#include <CLI/CLI.hpp>
#include <climits>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::app {

// The camera file `path`, or the default camera when `path` is empty.
camera::CatadioptricCamera load_camera(const std::string& path);

// With [sfm] refine_camera (from `config_file`), the batch's prior on `camera`, and with
// consider_camera the filter's camera_uncertainty, from the calibration's covariance in
// `camera_file`. Throws io::InputError naming the camera
// file when it holds no [omni_camera_covariance], or the config file when no camera file was
// given (`camera` null).
void apply_camera_prior(const std::string& config_file, const std::string& camera_file,
                        const camera::CatadioptricCamera* camera, sfm::SfmSettings* settings);

// The truth `--ground-truth` names (none when `path` is empty). Throws io::InputError naming it
// when it holds fewer than 3 poses: no alignment, so no figure, would come of it.
std::vector<io::StampedPose> read_ground_truth(const std::string& path);

// The vnlog table in `path`, or standard input when `path` is empty or "-".
io::VnlogTable read_table_or_stdin(const std::string& path);

// Flushes standard output; throws std::runtime_error when anything written was lost.
void finish_stdout();

// io::require_writable_folder for the folder that holds `path` (a file, or a folder to be made).
void require_writable_folder_of(const std::string& path);

// A file the verb writes into a folder that is made when missing, as sfm makes its --out folder:
// throws io::InputError naming `given` when `out` is a folder, or when the folder's (or, when it
// is missing, its parent's) is not a folder this process may write in.
void check_output_file(const std::string& given, const std::filesystem::path& out);
// Throws io::InputError naming `output` when it is one of `inputs` (the same file by any path;
// empty entries are skipped): writing it would destroy what the run reads.
void require_not_an_input(const std::string& output, const std::vector<std::string>& inputs);
// Runs `write` with `folder` made when missing; a folder made here goes again when `write` throws.
void in_folder_made_if_missing(const std::filesystem::path& folder,
                               const std::function<void()>& write);

// Option checks that say what is wanted as a person would (CLI11's ranges print their bounds with
// six decimals, and the largest double in 309 digits): "must be a number from 0 to 1, not '2'".
CLI::Validator number_between(double min, double max);
CLI::Validator positive_number();  // finite and > 0
// max = INT_MAX: no upper bound ("must be a whole number, at least 0").
CLI::Validator whole_number_between(int min, int max = INT_MAX);
// A random seed: digits only, within 64 bits (CLI11 wraps "-1" and 2^64 into a valid seed).
CLI::Validator seed_number();

}  // namespace omnisfm::app
