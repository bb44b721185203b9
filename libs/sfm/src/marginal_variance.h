#pragma once
// The marginal variance of one scalar parameter of a least-squares problem: the inverse of its
// information once every other free parameter is eliminated, from the Gauss-Newton information
// J^T J of the residuals as the solver weighs them (losses applied). Ceres' covariance would give
// the same from a sparse QR of the whole Jacobian, at four times the cost of the rover's whole
// batch solve; here the points are eliminated by their 3x3 blocks first, as the solver's Schur
// complement does, and only the reduced camera system is factored.

#include <ceres/ceres.h>

#include <vector>

namespace omnisfm::sfm {

// `problem` at its current values; `scalar` a variable block of size 1; `points` blocks of size 3
// that share no residual with one another (those absent from the problem or constant are
// skipped). INFINITY when the information is singular, i.e. nothing in the problem fixes
// `scalar`; NaN when `scalar` is not a variable block of the problem.
double marginal_variance(ceres::Problem* problem, double* scalar,
                         const std::vector<double*>& points);

}  // namespace omnisfm::sfm
