#pragma once
// What a calibration knows of some of the camera's parameters: their indices in
// CatadioptricCamera::params() (as a camera file's [omni_camera_covariance] names them) and their
// covariance, in the parameters' own units. The batch refines those parameters under it
// (BatchSettings::camera_prior); the filter carries their error in its covariance without
// estimating them (FilterSettings::camera_uncertainty).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::sfm {

struct CameraPrior {
  std::vector<int> parameters;
  Eigen::MatrixXd covariance;

  bool empty() const { return parameters.empty(); }
};

// What is wrong with `prior` for `camera` (a parameter out of range or listed twice, a
// covariance of the wrong size, not symmetric, not finite or not positive definite), or empty.
std::string camera_prior_problem(const camera::CatadioptricCamera& camera,
                                 const CameraPrior& prior);

}  // namespace omnisfm::sfm
