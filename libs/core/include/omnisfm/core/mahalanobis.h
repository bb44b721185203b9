#pragma once
// How far an error is in the units of a covariance: sqrt(e^T C^-1 e), the number of sigmas along
// the error's direction. NaN when C is not positive definite.

#include <Eigen/Cholesky>
#include <cmath>

namespace omnisfm::core {

inline double mahalanobis(const Eigen::VectorXd& error, const Eigen::MatrixXd& covariance) {
  const Eigen::LLT<Eigen::MatrixXd> factor(covariance);
  if (factor.info() != Eigen::Success) return NAN;
  return std::sqrt(error.dot(factor.solve(error)));
}

}  // namespace omnisfm::core
