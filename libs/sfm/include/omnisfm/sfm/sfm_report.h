#pragma once
// The lines report.txt holds on a shape-from-motion result, which the sfm, run and demo verbs
// write (as calib/calibration_report.h holds a calibration's).

#include <string>
#include <vector>

#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::sfm {

// "outlier tracks N", how many of the filter's rejections the batch took back, and the noise
// they were judged at where the filter measured more than `stated_noise_px` (pixel_sigma).
std::string outliers_phrase(const SfmResult& result, double stated_noise_px);

// Where more than half of at least 10 tracks (seen twice or more) were rejected, "N of M tracks
// were rejected as outliers: " and the likeliest causes under `settings` (the outlier test and
// its bound, pixel_sigma against `taken_noise_px`, the noise the filter took:
// SfmResult::online_noise_px); else "".
std::string most_rejected_phrase(long rejected, long tracks, double taken_noise_px,
                                 const FilterSettings& settings);
// The same as the report's line, beginning "warning: " and ending in a newline; else "".
std::string most_rejected_line(long rejected, long tracks, double taken_noise_px,
                               const FilterSettings& settings);

// The filter alone: "; N observations of new tracks left out for want of room (max_live_points)"
// where it left any out (OnlineFilter::not_admitted), else "".
std::string not_admitted_phrase(long observations);

// Where the images refused the vehicle's sensors' motion into `count` frames
// (OnlineFilter::on_motion_refused), the line beginning "motion sensors refused:" and ending in a
// newline, listing the first of `frames` (none for the filter alone, which counts them only),
// and what was done instead; else "".
std::string refused_motion_line(long count, const std::vector<int>& frames, bool batch);

// "; N fixes refused, at odds with the rest ... (at t1, t2 ... s)" where the fusion left GPS
// fixes out (SfmResult::refused_gps_fixes, indices into sensors.gps), else "".
std::string refused_fixes_phrase(const MotionSensors& sensors, const std::vector<int>& refused);

// " (judged at the tracks' measured noise, ...)" where `taken_px` is beyond `stated_px`, else "".
std::string measured_noise_phrase(double taken_px, double stated_px);

// The batch's solve, ending in a newline: "batch: converged in N iterations, S s; RMS a -> b px
// per coordinate (the solver's message)".
std::string batch_line(const BatchResult& batch);

// The batch's scale, beginning "scale:" and ending in a newline: where it comes from, its
// relative standard deviation (with the camera refined, that and the one with the camera as
// calibrated, which decided), and "held" (why, and where) when the batch held it.
std::string scale_line(const SfmResult& result, const BatchSettings& settings);

// With the camera refined (BatchSettings::camera_prior), the line beginning "camera:" and ending
// in a newline: each refined parameter's move from the calibrated `camera`, in its units and in
// the calibration's sigmas, and the move's distance in those sigmas (Mahalanobis); not refined,
// that the camera was held as calibrated, and why. Empty without a prior.
std::string camera_line(const camera::CatadioptricCamera& camera, const BatchResult& batch,
                        const BatchSettings& settings);

// With the camera's calibration uncertainty considered by the filter
// (FilterSettings::camera_uncertainty), the line beginning "filter's camera:" and ending in a
// newline, naming the parameters; empty without.
std::string considered_camera_line(const camera::CatadioptricCamera& camera,
                                   const FilterSettings& settings);

}  // namespace omnisfm::sfm
