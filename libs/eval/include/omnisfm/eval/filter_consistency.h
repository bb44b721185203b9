#pragma once
// The online filter's published pose covariance against its actual errors on the simulated rover
// with its simulated odometry and gyro: the normalised estimation error squared (NEES) of the pose
// at every frame but the first (rotation as a left perturbation, then translation, of
// cam_from_world, in the gauge of the first frame). Honest: a mean of 6 (the pose's degrees of
// freedom) and 95 % of frames inside chi-square(6)'s 95 % bound, 12.59.

#include "omnisfm/sfm/camera_prior.h"
#include "omnisfm/sfm/online_filter.h"

namespace omnisfm::eval {

// The filter's pose error as its covariance (OnlineFilter::pose_covariance) states it: the
// rotation's left perturbation of cam_from_world, then the translation's.
Eigen::Matrix<double, 6, 1> filter_pose_error(const Eigen::Isometry3d& true_cam_from_world,
                                              const Eigen::Isometry3d& estimated_cam_from_world);

struct PoseConsistency {
  double mean_nees = 0;
  double inside = 0;  // the fraction of frames inside the 95 % bound
  long frames = 0;
};

// Rover seeds 1..seeds, the simulated wheel reading `wheel_scale_error` long (0.015: 1.5 %).
// linearised_at_truth: the filter takes its Jacobians at the true poses and points
// (OnlineFilter::linearise_at), which shows what the filter's model alone is worth.
// calibration_error: the filter's camera is not the rover's but a calibration of it, drawn per
// seed from this covariance about the truth (calibrated_with_error, seeded 1000 + the seed),
// its parameters' errors scaled by `error_sigmas`; the filter is told of it only through
// settings.camera_uncertainty.
PoseConsistency rover_pose_consistency(int seeds, double wheel_scale_error,
                                       const sfm::FilterSettings& settings = {},
                                       bool linearised_at_truth = false,
                                       const sfm::CameraPrior* calibration_error = nullptr,
                                       double error_sigmas = 1);

}  // namespace omnisfm::eval
