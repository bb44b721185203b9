#pragma once
// Imperfect calibrations of a simulated rig, for studies of what a calibration's error costs: the
// rig moved by a draw from a calibration's covariance, and a camera's distance from the truth in
// a covariance's sigmas.

#include <Eigen/Core>
#include <cstdint>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/sfm/batch_adjustment.h"

namespace omnisfm::eval {

// `truth` moved by L z on the prior's parameters (L L^T its covariance), z standard normal from
// `seed`: a calibration that erred as its covariance says it may.
camera::CatadioptricCamera calibrated_with_error(const camera::CatadioptricCamera& truth,
                                                 const sfm::CameraPrior& prior,
                                                 std::uint64_t seed);

// The Mahalanobis distance of `params` (as CatadioptricCamera::params()) from the truth's over
// the prior's parameters, under `covariance` (of those parameters, in the prior's order); NaN
// when it is not positive definite. Throws std::invalid_argument for params of another size.
double sigmas_from_truth(const Eigen::VectorXd& params, const camera::CatadioptricCamera& truth,
                         const sfm::CameraPrior& prior,
                         const Eigen::MatrixXd& covariance);

}  // namespace omnisfm::eval
