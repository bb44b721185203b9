#pragma once
// The estimators' settings from an INI file, section [sfm]; absent keys keep their defaults. The
// ranges hold what a value can mean (share/omnisfm/config/omnisfm.ini says what each is):
//   pixel_sigma (0.001-100 px)  rotation_walk_sigma (0-3.14 rad)
//   translation_walk_sigma (1e-6-1e6 m)  initial_depth (0.001-1e6 m)
//   inverse_depth_sigma (1e-6-1e6 /m)  outlier_test (chi2 or pixels)  outlier_chi2 (>= 5.99)
//   outlier_threshold_px (0.01-1e6)  innovation_gate_chi2 (0: off, or >= 5.99)
//   measure_noise (0 or 1)  update_iterations (1-100)  linearise_at_constant_velocity (0 or 1)
//   smoothed_start_frames (0 or >= 2)  smoothing_window_frames (0: off)  max_live_points (6-1000)
//   batch  (0 or 1)  batch_outliers (0 or 1)  batch_outlier_threshold_px (0 or 0.01-1e6)
//   batch_track_false_alarm (0 <= it < 1)  huber_px (0 or 0.01-1e6)
//   covariances (0 or 1)  max_iterations (1-1e6)
//   batch_scale_start (0 or 1)  known_distance_m (0.001-1e8 m, or empty: not known)
//   refine_camera (0 or 1)  consider_camera (0 or 1)

#include <string>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/io/ini_file.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::sfm {

// Throws io::InputError naming the file, the key and its line for an unknown key, a non-number or
// a value out of range, a key before any section, or a section other than [sfm] and [run] (the
// run verb's, which a file may hold for both verbs).
SfmSettings read_sfm_settings(const std::string& path);
// The same from a section already read (its name is not checked).
SfmSettings read_sfm_settings(const io::IniSection& section);

// The batch's prior on `camera` from its calibration's covariance (io::read_camera_covariance):
// the named parameters' indices in camera.params(). Throws std::invalid_argument for a name the
// camera does not have, or a covariance the batch cannot use (camera_prior_problem).
CameraPrior camera_prior_from(const camera::CatadioptricCamera& camera,
                                             const io::ParameterCovariance& covariance);

}  // namespace omnisfm::sfm
