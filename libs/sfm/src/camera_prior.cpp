#include "omnisfm/sfm/camera_prior.h"

#include <Eigen/Cholesky>
#include <set>

namespace omnisfm::sfm {

std::string camera_prior_problem(const camera::CatadioptricCamera& camera,
                                 const CameraPrior& prior) {
  const auto k = static_cast<Eigen::Index>(prior.parameters.size());
  if (k == 0)
    return prior.covariance.size() == 0 ? "" : "a covariance is given for no parameters";
  std::set<int> seen;
  for (int p : prior.parameters) {
    if (p < 0 || p >= camera.num_params())
      return "parameter " + std::to_string(p) + " is not one of the camera's " +
             std::to_string(camera.num_params());
    if (!seen.insert(p).second) return "parameter " + std::to_string(p) + " is listed twice";
  }
  if (prior.covariance.rows() != k || prior.covariance.cols() != k)
    return "the covariance is " + std::to_string(prior.covariance.rows()) + " x " +
           std::to_string(prior.covariance.cols()) + " for " + std::to_string(k) + " parameters";
  if (!prior.covariance.allFinite() || !prior.covariance.isApprox(prior.covariance.transpose()))
    return "the covariance is not a finite symmetric matrix";
  if (Eigen::LLT<Eigen::MatrixXd>(prior.covariance).info() != Eigen::Success)
    return "the covariance is not positive definite (a parameter known exactly, or two that are "
           "the same): leave such parameters out";
  return "";
}

}  // namespace omnisfm::sfm
