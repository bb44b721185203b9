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
  // The map's scale at each seed's last frame: the estimated over the true distance of the camera
  // from the first, its logarithm over the published sigma (OnlineFilter::vision_scale_log_sigma),
  // squared, averaged over the seeds (1 when honest). 0 with the sensors.
  double mean_scale_nees = 0;
  // The same linearised as the published covariance holds it: the translation's error along
  // itself, (1 - 1/scale), over the sigma, squared, averaged over the seeds (at most 1 when
  // honest or cautious).
  double mean_linearised_scale_nees = 0;
  double largest_scale = 0, smallest_scale = 0;  // over the seeds, vision alone
};

// What rover_pose_consistency runs.
struct RoverStudy {
  // How long the simulated wheel reads (0.015: 1.5 %).
  double wheel_scale_error = 0.015;
  // False: the camera alone (the filter's covariance then holds the map's scale,
  // OnlineFilter::vision_scale_log_sigma).
  bool with_sensors = true;
  // The filter takes its Jacobians at the true poses and points (OnlineFilter::linearise_at),
  // which shows what the filter's model alone is worth.
  bool linearised_at_truth = false;
  // Non-null: the filter's camera is not the rover's but a calibration of it, drawn per seed from
  // this covariance about the truth (calibrated_with_error, seeded 1000 + the seed), its
  // parameters' errors scaled by error_sigmas; the filter is told of it only through
  // FilterSettings::camera_uncertainty.
  const sfm::CameraPrior* calibration_error = nullptr;
  double error_sigmas = 1;
};

// Rover seeds 1..seeds.
PoseConsistency rover_pose_consistency(int seeds, const sfm::FilterSettings& settings = {},
                                       const RoverStudy& study = {});

}  // namespace omnisfm::eval
