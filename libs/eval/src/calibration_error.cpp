#include "omnisfm/eval/calibration_error.h"

#include <Eigen/Cholesky>
#include <random>
#include <stdexcept>
#include <string>

#include "omnisfm/core/mahalanobis.h"

namespace omnisfm::eval {

camera::CatadioptricCamera calibrated_with_error(const camera::CatadioptricCamera& truth,
                                                 const sfm::CameraPrior& prior,
                                                 std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd z(prior.parameters.size());
  for (Eigen::Index i = 0; i < z.size(); ++i) z(i) = normal(rng);
  const Eigen::VectorXd step = prior.covariance.llt().matrixL() * z;
  Eigen::VectorXd params = truth.params();
  for (size_t k = 0; k < prior.parameters.size(); ++k)
    params(prior.parameters[k]) += step(static_cast<Eigen::Index>(k));
  camera::CatadioptricCamera camera = truth;
  if (!camera.set_params(params))
    throw std::invalid_argument("a draw from the covariance is not a valid camera");
  return camera;
}

double sigmas_from_truth(const Eigen::VectorXd& params, const camera::CatadioptricCamera& truth,
                         const sfm::CameraPrior& prior,
                         const Eigen::MatrixXd& covariance) {
  if (params.size() != truth.num_params())
    throw std::invalid_argument("sigmas_from_truth: " + std::to_string(params.size()) +
                                " parameters for a camera of " +
                                std::to_string(truth.num_params()));
  const Eigen::VectorXd true_params = truth.params();
  Eigen::VectorXd error(prior.parameters.size());
  for (Eigen::Index i = 0; i < error.size(); ++i)
    error(i) = params(prior.parameters[i]) - true_params(prior.parameters[i]);
  return core::mahalanobis(error, covariance);
}

}  // namespace omnisfm::eval
