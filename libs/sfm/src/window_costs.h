#pragma once
// The sliding window's terms (online_filter_window.cpp) as Ceres cost functions, with analytic
// Jacobians; pose blocks as the smoothed start's (start_window_costs.h).

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "omnisfm/sfm/filter_state.h"
#include "so3.h"
#include "start_window_costs.h"

namespace omnisfm::sfm {

// A Gaussian prior over several blocks at once, L^-1 (x - mean) with L L^T their covariance; a
// pose block's rotation is its offset from the reference rotation, whose mean is zero.
class JointPriorCost : public ceres::CostFunction {
 public:
  JointPriorCost(Eigen::MatrixXd whitening, Eigen::VectorXd mean, const std::vector<int>& sizes)
      : whitening_(std::move(whitening)), mean_(std::move(mean)) {
    set_num_residuals(static_cast<int>(mean_.size()));
    for (const int size : sizes) mutable_parameter_block_sizes()->push_back(size);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const std::vector<int32_t>& sizes = parameter_block_sizes();
    Eigen::VectorXd x(mean_.size());
    int at = 0;
    for (size_t b = 0; b < sizes.size(); ++b)
      for (int k = 0; k < sizes[b]; ++k) x[at++] = parameters[b][k];
    Eigen::Map<Eigen::VectorXd>(residuals, mean_.size()) = whitening_ * (x - mean_);
    if (!jacobians) return true;
    at = 0;
    for (size_t b = 0; b < sizes.size(); ++b) {
      if (jacobians[b])
        Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
            jacobians[b], mean_.size(), sizes[b]) = whitening_.middleCols(at, sizes[b]);
      at += sizes[b];
    }
    return true;
  }

 private:
  Eigen::MatrixXd whitening_;
  Eigen::VectorXd mean_;
};

// A ray's start that moves with the pose it was started from: R^T (o - t), o its start in the
// camera's frame; and how it moves with that pose (a left perturbation, then the translation).
struct MovingOrigin {
  Eigen::Vector3d in_camera = Eigen::Vector3d::Zero();  // o
  Eigen::Vector3d placed = Eigen::Vector3d::Zero();  // the anchor's, R^T (o - t) at that pose then
  Eigen::Vector3d offset(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) const {
    return R.transpose() * (in_camera - t) - placed;
  }
  Eigen::Matrix<double, 3, 6> jacobian(const Eigen::Matrix3d& R, const Eigen::Vector3d& t) const {
    Eigen::Matrix<double, 3, 6> J;
    J << R.transpose() * so3::skew(in_camera - t), -R.transpose();
    return J;
  }
};

// The pixel of a point, with its Jacobians in the pose (left perturbation) and the point's six
// parameters; false where it does not project.
using PointPixel = std::function<bool(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                                      const PointParams& params, bool jacobians,
                                      Eigen::Vector2d* pixel, Eigen::Matrix<double, 2, 6>* J_pose,
                                      Eigen::Matrix<double, 2, 6>* J_point)>;

// sigma^-1 (pixel - observed) of a point seen from a pose of the window. Blocks: the pose, then
// either the point's six parameters (a point the prior holds), or, for a point started in the
// window, the pose it was started from (unless that is this pose), then its angles and inverse
// depth, its origin's offset following that pose.
class WindowPixelCost : public ceres::CostFunction {
 public:
  static WindowPixelCost* of_prior_point(PointPixel model, const Eigen::Matrix3d* R_ref,
                                         Eigen::Vector2d observed, double sigma) {
    return new WindowPixelCost(std::move(model), R_ref, false, nullptr, {}, observed, sigma);
  }
  // R_start: the reference rotation of the pose it was started from; null when that is this pose.
  static WindowPixelCost* of_started_point(PointPixel model, const Eigen::Matrix3d* R_ref,
                                           const Eigen::Matrix3d* R_start, MovingOrigin origin,
                                           Eigen::Vector2d observed, double sigma) {
    return new WindowPixelCost(std::move(model), R_ref, true, R_start, origin, observed, sigma);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* pose = parameters[0];
    const Eigen::Matrix3d R = rotation_of(pose, *R_ref_);
    const Eigen::Vector3d t(pose[3], pose[4], pose[5]);
    const double* start = R_start_ ? parameters[1] : pose;
    const Eigen::Matrix3d R_start = R_start_ ? rotation_of(start, *R_start_) : R;
    const Eigen::Vector3d t_start(start[3], start[4], start[5]);
    const double* point = parameters[R_start_ ? 2 : 1];
    PointParams params;
    if (started_)
      params << Eigen::Map<const Eigen::Vector3d>(point), origin_.offset(R_start, t_start);
    else
      params = Eigen::Map<const PointParams>(point);
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 6> J_pose, J_point;
    if (!model_(R, t, params, jacobians != nullptr, &pixel, &J_pose, &J_point)) return false;
    Eigen::Map<Eigen::Vector2d> r(residuals);
    r = weight_ * (pixel - observed_);
    if (!jacobians) return true;
    using Block = Eigen::Matrix<double, 2, 6, Eigen::RowMajor>;
    if (!started_) {
      if (jacobians[0]) Block::Map(jacobians[0]) = weight_ * in_block<2>(J_pose, pose);
      if (jacobians[1]) Block::Map(jacobians[1]) = weight_ * J_point;
      return true;
    }
    const Eigen::Matrix<double, 2, 6> J_start =
        J_point.rightCols<3>() * origin_.jacobian(R_start, t_start);
    if (R_start_) {
      if (jacobians[0]) Block::Map(jacobians[0]) = weight_ * in_block<2>(J_pose, pose);
      if (jacobians[1]) Block::Map(jacobians[1]) = weight_ * in_block<2>(J_start, start);
    } else if (jacobians[0]) {
      Block::Map(jacobians[0]) = weight_ * in_block<2>(J_pose + J_start, pose);
    }
    if (double* J = jacobians[R_start_ ? 2 : 1])
      Eigen::Matrix<double, 2, 3, Eigen::RowMajor>::Map(J) = weight_ * J_point.leftCols<3>();
    return true;
  }

 private:
  WindowPixelCost(PointPixel model, const Eigen::Matrix3d* R_ref, bool started,
                  const Eigen::Matrix3d* R_start, MovingOrigin origin, Eigen::Vector2d observed,
                  double sigma)
      : model_(std::move(model)), R_ref_(R_ref), started_(started), R_start_(R_start),
        origin_(origin), observed_(observed), weight_(1 / sigma) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(6);
    if (R_start_) mutable_parameter_block_sizes()->push_back(6);
    mutable_parameter_block_sizes()->push_back(started_ ? 3 : 6);
  }

  PointPixel model_;
  const Eigen::Matrix3d* R_ref_;
  bool started_;
  const Eigen::Matrix3d* R_start_;
  MovingOrigin origin_;
  Eigen::Vector2d observed_;
  double weight_;
};

}  // namespace omnisfm::sfm
