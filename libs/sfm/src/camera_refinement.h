#pragma once
// The camera as a parameter block of the batch (BatchSettings::camera_prior): the reprojection
// residual with the camera's params() as a fourth block, and the calibration's prior on them.

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/camera/shared_camera.h"
#include "projection_cost.h"

namespace omnisfm::sfm {

// ScaledProjectionCost's residual with the camera's params() as a fourth parameter block, the
// camera at that block's values kept by the problem's camera::SharedCamera.
class RefinedProjectionCost : public ceres::CostFunction {
 public:
  RefinedProjectionCost(const camera::SharedCamera* camera, const Eigen::Vector2d& pixel)
      : camera_(camera), pixel_(pixel) {
    set_num_residuals(2);
    *mutable_parameter_block_sizes() = {6, 3, 1, camera->camera().num_params()};
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!(parameters[2][0] > 0) || !camera_->valid()) return false;  // past infinity; refused
    const camera::CatadioptricCamera& camera = camera_->camera();
    const bool params_jacobian = jacobians && jacobians[3];
    thread_local camera::ParamsJacobian J_params;
    if (!evaluate_projection(camera, pixel_, parameters[0], parameters[1], parameters[2][0],
                             residuals, jacobians ? jacobians[0] : nullptr,
                             jacobians ? jacobians[1] : nullptr, jacobians ? jacobians[2] : nullptr,
                             params_jacobian ? &J_params : nullptr))
      return false;
    if (params_jacobian)
      Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>>(
          jacobians[3], 2, camera.num_params()) = J_params;
    return true;
  }

 private:
  const camera::SharedCamera* camera_;
  Eigen::Vector2d pixel_;
};

// A calibration's Gaussian prior on some of the camera's params(): `weight` L^-1 (params[i] -
// calibrated[i]) over the listed i, with L L^T their covariance (positive definite:
// camera_prior_problem). `weight` puts it in the units of the residuals it sits among (the pixel
// noise where those are in pixels).
class CameraPriorCost : public ceres::CostFunction {
 public:
  CameraPriorCost(const Eigen::VectorXd& calibrated, const std::vector<int>& parameters,
                  const Eigen::MatrixXd& covariance, double weight)
      : calibrated_(calibrated), parameters_(parameters) {
    const Eigen::MatrixXd L = covariance.llt().matrixL();
    whitening_ = weight * L.triangularView<Eigen::Lower>().solve(
                              Eigen::MatrixXd::Identity(L.rows(), L.cols()));
    set_num_residuals(static_cast<int>(parameters.size()));
    *mutable_parameter_block_sizes() = {static_cast<int>(calibrated.size())};
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = static_cast<int>(parameters_.size());
    Eigen::VectorXd moved(k);
    for (int i = 0; i < k; ++i)
      moved(i) = parameters[0][parameters_[i]] - calibrated_(parameters_[i]);
    Eigen::Map<Eigen::VectorXd>(residuals, k) = whitening_ * moved;
    if (jacobians && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
          jacobians[0], k, calibrated_.size());
      J.setZero();
      for (int i = 0; i < k; ++i) J.col(parameters_[i]) = whitening_.col(i);
    }
    return true;
  }

 private:
  Eigen::VectorXd calibrated_;
  std::vector<int> parameters_;
  Eigen::MatrixXd whitening_;
};

}  // namespace omnisfm::sfm
