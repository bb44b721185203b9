#pragma once
// The pipeline with the vehicle's own motion sensors: the online filter propagated by the
// odometry and the gyro (motion_prediction.h) instead of the random walk, then the batch with the
// odometry's planar increments, the gyro's relative rotations (and its bias, one constant per
// run) and the GPS antenna positions as residuals beside the reprojections (motion_residuals.h).
//
// The world frame of every pose and point in the result:
//   - with GPS fixes: the GPS's local east-north-up frame (result.world_is_enu). The filter runs
//     in the first camera's frame; its estimate is then moved into ENU by the similarity (rigid,
//     with odometry) that best fits its antenna positions to the fixes, and the batch holds no
//     pose: the fixes fix the gauge. They must span at least 3 non-collinear positions (the
//     rotation about a straight path is not observable otherwise): where they do not, it throws,
//     or with SfmSettings::leave_out_unplaceable_gps leaves them all out (the world is then the
//     first camera's frame; SfmResult::gps_left_out says why). A fix at odds with the rest
//     as the filter's trajectory places them (beyond its own noise's 1 - 1e-6 bound, and five
//     times the fixes' robust spread about the fit) is left out of both, and listed in
//     result.refused_gps_fixes.
//   - otherwise: the first camera's frame, its pose the identity, as run_sfm's. With odometry the
//     scale is metric (the odometry's, times its estimated scale: see MotionSensors::
//     odometry_scale); with a gyro alone it is only as good as the noncentral camera makes it.
// The batch weighs the reprojections by settings.filter.pixel_sigma, the sensors' terms by their
// noise models. The odometry's scale and the gyro's bias it estimates come back in
// result.odometry_scale and result.gyro_bias (the scale is held at MotionSensors::odometry_scale
// when there is no batch or scale_sigma is 0), with their standard deviations when the batch
// computes covariances.

#include <string>
#include <vector>

#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::sfm {

// frame_timestamps: one per frame (at least as many as the tracks span), increasing, on the
// sensors' clock. With empty sensors this is run_sfm. Throws as run_sfm does, and
// std::invalid_argument for missing or non-increasing timestamps and, unless
// settings.leave_out_unplaceable_gps, for GPS fixes too few or all on a line within the frames'
// time span.
SfmResult run_fused_sfm(const camera::CatadioptricCamera& camera,
                        const std::vector<core::TrackObservation>& tracks,
                        const std::vector<double>& frame_timestamps, const MotionSensors& sensors,
                        const SfmSettings& settings, const Progress& progress = nullptr);

// The GPS fixes within the frames' time span (but the `refused_fixes`, indices into
// sensors.gps) against an estimate in their ENU frame: each fix against the antenna's position
// between the frames around it, as the batch's GPS terms see it.
struct GpsResiduals {
  int fixes = 0;
  double rms_m = 0;
};
GpsResiduals gps_residuals(const std::vector<Eigen::Isometry3d>& world_from_cam,
                           const std::vector<double>& frame_timestamps,
                           const MotionSensors& sensors,
                           const std::vector<int>& refused_fixes = {});

}  // namespace omnisfm::sfm
