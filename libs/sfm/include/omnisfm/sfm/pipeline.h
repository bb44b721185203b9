#pragma once
// The paper's pipeline: the online filter over the tracks, frame by frame, then the batch
// adjustment over all frames, started from the filter and run on its inliers.

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "omnisfm/core/track_observation.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/online_filter.h"

namespace omnisfm::sfm {

struct SfmSettings {
  FilterSettings filter;
  BatchSettings batch;
  bool run_batch = true;
  // Whether the batch refines the camera under its calibration's covariance: the programs then
  // fill batch.camera_prior from the camera file's [omni_camera_covariance]
  // (sfm::camera_prior_from, settings_file.h). The batch refines the camera whenever that prior
  // lists parameters; run_sfm refuses this flag without one.
  bool refine_camera = false;
  // Whether the filter carries the same covariance as its camera's uncertainty
  // (FilterSettings::camera_uncertainty), filled the same way; run_sfm refuses this flag without
  // it.
  bool consider_camera = false;
  // After the batch, a track with a residual beyond this is rejected too, a track the filter
  // rejected that fits the batch's poses within it is taken back, and the batch re-run: a track
  // that slid to a nearby feature can fool the filter's test but not the whole sequence, and a
  // good track the filter rejected while its depth was unknown fits it. 0 turns both off.
  bool batch_outliers = true;
  double batch_outlier_threshold_px = 2.0;  // with OutlierTest::kPixels; 0 is off too
  // With the batch's re-test on (a residual limit above 0), a track whose residuals over its
  // length a good track would exceed with this probability, at the filter's pixel_sigma (or the
  // tracks' own noise where larger), is rejected too, and a track the filter rejected is taken
  // back only if it passes (track_consistency.h): a slow drift stays within the residual limit
  // at every frame. 0 turns it off; run_sfm refuses 1 or more.
  double batch_track_false_alarm = 1e-4;
  // GPS fixes too few or on a line (within their noise) to place the estimate in ENU, a straight
  // drive or a rawlog cut short, also once those at odds with the rest are left out
  // (run_fused_sfm): false throws; true leaves every fix out of the move into ENU and of the
  // batch, the estimate staying in the first camera's frame, and says why in
  // SfmResult::gps_left_out.
  bool leave_out_unplaceable_gps = false;
  // The batch's limit on a residual: 0 when its test is off, else batch_outlier_threshold_px
  // with the paper's test and FilterSettings::residual_limit_px() with the chi-square one.
  double batch_residual_limit_px() const;
};

struct SfmResult {
  int num_frames = 0;
  // Tracks seen in two frames or more: a track seen once is neither a point nor an outlier.
  int num_tracks = 0;
  std::vector<Eigen::Isometry3d> online_world_from_cam;  // the filter's estimate at each frame
  std::map<int, Eigen::Vector3d> online_points;
  // The filter's, less those the batch took back, then the batch's.
  std::vector<RejectedTrack> outliers;
  int taken_back = 0;  // tracks the filter rejected that the batch's solution explains
  // Tracks the filter had no room for (FilterSettings::max_live_points), and of them those the
  // batch placed by triangulation from the filter's poses and took.
  int not_in_filter = 0, placed_by_triangulation = 0;
  // Why the batch did not re-test the tracks against its solution (empty when it did, or when
  // batch_outliers is off): a solution that does not fit the tracks would reject good ones.
  std::string retest_skipped;
  // Frames whose motion from the previous frame the vehicle's sensors mispredicted, as the
  // images showed (OnlineFilter::on_motion_refused): the batch leaves those intervals' odometry
  // and gyro out.
  std::vector<int> refused_motion_frames;
  // GPS fixes at odds with the rest as the filter's trajectory places them (a multipath jump),
  // indices into MotionSensors::gps: left out of the move into ENU and of the batch.
  std::vector<int> refused_gps_fixes;
  double online_seconds = 0;
  // The tracks' noise the filter took at the last frame, pixels per coordinate: pixel_sigma, or
  // what it measured where well beyond (FilterSettings::measure_noise).
  double online_noise_px = NAN;
  BatchResult batch;
  // With the vehicle's motion sensors (run_fused_sfm, fused_pipeline.h):
  // Why the GPS fixes were all left out (SfmSettings::leave_out_unplaceable_gps); "" otherwise.
  std::string gps_left_out;
  bool world_is_enu = false;           // the world is the GPS's local ENU frame, else the first camera's
  double odometry_scale = 1;           // estimated: true distance per distance the odometry read
  Eigen::Vector3d gyro_bias{0, 0, 0};  // estimated, rad/s about the body's axes
  // The filter's own estimate of the gyro's bias at the last frame, with its standard deviations
  // (zero and NaN without a gyro, or with FilterSettings::estimate_gyro_bias off).
  Eigen::Vector3d online_gyro_bias{0, 0, 0};
  Eigen::Vector3d online_gyro_bias_sigma = Eigen::Vector3d::Constant(NAN);
  // And its correction of the wheels' calibrated scale (MotionSensors::odometry_scale), with its
  // standard deviation (1 and NaN without odometry).
  double online_wheel_scale = 1;
  double online_wheel_scale_sigma = NAN;
  // Their standard deviations from the batch's covariance; NaN when not computed
  // (BatchSettings::covariances off) or when the value was held.
  double odometry_scale_sigma = NAN;
  Eigen::Vector3d gyro_bias_sigma = Eigen::Vector3d::Constant(NAN);
};

// Called after each frame the filter processes: (frames done, frames in all).
using Progress = std::function<void(int, int)>;

// Throws std::invalid_argument when the tracks cannot support an estimate (no frames, fewer than
// 6 tracks in the first frame), and std::runtime_error when the motion is degenerate (the camera
// translates by less than 1 % of the scene's depth: rotation alone reveals no structure).
SfmResult run_sfm(const camera::CatadioptricCamera& camera,
                  const std::vector<core::TrackObservation>& tracks, const SfmSettings& settings,
                  const Progress& progress = nullptr);

// Each frame's observations (frames 0 .. last observed), as OnlineFilter::process_frame takes
// them. Throws std::invalid_argument as run_sfm does.
std::vector<std::vector<TrackPixel>> observations_by_frame(
    const std::vector<core::TrackObservation>& tracks);

}  // namespace omnisfm::sfm
