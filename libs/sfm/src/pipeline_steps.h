#pragma once
// The steps of the shape-from-motion pipeline that the vision-only and the fused pipelines share.

#include <functional>
#include <vector>

#include "batch_terms.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::sfm {

// The filter over every frame, into result's online estimate and outliers; predicted_motion, when
// set, gives the motion into frame f (f >= 1) in place of the random walk, at the filter's
// estimates of the sensors. Returns the filter's poses as its state held them, cam_from_world per
// frame: the batch starts from these, not from result's world_from_cam turned back.
using PredictedMotion = std::function<MotionPrediction(int frame, const SensorStates& states)>;
std::vector<Eigen::Isometry3d> run_filter(const camera::CatadioptricCamera& camera,
                                          const std::vector<std::vector<TrackPixel>>& by_frame,
                                          const FilterSettings& settings,
                                          const PredictedMotion& predicted_motion,
                                          const Progress& progress, SfmResult* result);

// The tracks seen in two frames or more (SfmResult::num_tracks).
int tracks_seen_twice(const std::vector<core::TrackObservation>& tracks);

// Throws std::invalid_argument, before any work, for settings that cannot be run: refine_camera
// without the camera's prior to refine it under, consider_camera without the uncertainty to
// consider, either prior unusable (camera_prior_problem), or a batch_track_false_alarm that is
// no probability below 1.
void check_settings(const camera::CatadioptricCamera& camera, const SfmSettings& settings);

// Throws std::runtime_error when the filter's camera barely translates against the scene's depth,
// saying why where it can: the filter rejected most tracks, or (without `odometry`, where the walk
// moves the camera) its translation walk held the camera still.
void refuse_degenerate_motion(const SfmResult& result, const FilterSettings& settings,
                              bool odometry);

// The batch started from the filter (online_cam_from_world, as run_filter returns it) on its
// inliers, then the batch-level outlier rejection and the batch again; fills result->batch and
// adds to result->outliers.
void adjust_on_inliers(const camera::CatadioptricCamera& camera,
                       const std::vector<core::TrackObservation>& tracks, const SfmSettings& settings,
                       const std::vector<Eigen::Isometry3d>& online_cam_from_world,
                       ExtraTerms* extra, SfmResult* result);

}  // namespace omnisfm::sfm
