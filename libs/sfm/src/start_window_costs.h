#pragma once
// The smoothed start's terms (online_filter_smoothed_start.cpp) as Ceres cost functions, with the
// filter's analytic Jacobians. A pose of the window is a block of six, (w, t): R = Exp(w) R_ref
// with R_ref the rotation the solve started from, so that a block's rotation Jacobian is the
// filter's (a left perturbation) times J_left(w).

#include <ceres/cost_function.h>
#include <ceres/solver.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <functional>

#include "motion_prior_residual.h"
#include "so3.h"

namespace omnisfm::sfm {

using PoseBlock = Eigen::Matrix<double, 6, 1>;

// A window of a few tens of frames and a hundred points: one thread (a filter runs frame by
// frame), the points eliminated where nothing but measurements ties them (the sliding window's
// prior ties the points it holds to its first pose, and those stay in the reduced system).
// Levenberg-Marquardt starting nearly as Gauss-Newton, from the filter's own estimate; stopping
// once a step lowers the cost by a small fraction of what is left.
inline ceres::Solver::Options window_solver_options() {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.num_threads = 1;
  options.max_num_iterations = 50;
  options.initial_trust_region_radius = 1e6;
  options.function_tolerance = 1e-8;
  options.logging_type = ceres::SILENT;
  return options;
}

// Variances below this (a walk sigma of 0: the pose cannot move; a translation the state origin's
// move made exact) are held at it, so that the normal equations stay factorable.
constexpr double kMinVariance = 1e-12;

inline Eigen::Matrix3d rotation_of(const double* pose, const Eigen::Matrix3d& reference) {
  return so3::exp(Eigen::Map<const Eigen::Vector3d>(pose)) * reference;
}

// A left-perturbation Jacobian's columns (rotation, translation) as the block's.
template <int Rows>
Eigen::Matrix<double, Rows, 6> in_block(const Eigen::Matrix<double, Rows, 6>& left,
                                        const double* pose) {
  Eigen::Matrix<double, Rows, 6> J = left;
  J.template leftCols<3>() =
      left.template leftCols<3>() * so3::left_jacobian(Eigen::Map<const Eigen::Vector3d>(pose));
  return J;
}

// A pixel as the filter predicts it from a pose (R, t) and a point's three solved parameters,
// with its Jacobians (pose as a left perturbation, then the point) when asked. False where the
// point does not project.
struct PixelPrediction {
  Eigen::Vector2d pixel;
  Eigen::Matrix<double, 2, 6> pose;
  Eigen::Matrix<double, 2, 3> point;
};
using PixelModel = std::function<bool(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                                      const Eigen::Vector3d& point, bool jacobians,
                                      PixelPrediction* out)>;

// sigma^-1 (predicted - observed). Blocks: the pose (unless it is the window's first, which fixes
// the gauge and is then given as `fixed_t`), the point.
class StartPixelCost : public ceres::CostFunction {
 public:
  StartPixelCost(PixelModel model, const Eigen::Matrix3d* R_ref, const Eigen::Vector3d* fixed_t,
                 Eigen::Vector2d observed, double sigma)
      : model_(std::move(model)), R_ref_(R_ref), fixed_t_(fixed_t), observed_(observed),
        weight_(1 / sigma) {
    set_num_residuals(2);
    if (!fixed_t_) mutable_parameter_block_sizes()->push_back(6);
    mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* pose = fixed_t_ ? nullptr : parameters[0];
    const double* point = parameters[fixed_t_ ? 0 : 1];
    const Eigen::Matrix3d R = pose ? rotation_of(pose, *R_ref_) : *R_ref_;
    const Eigen::Vector3d t = pose ? Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(pose + 3))
                                   : *fixed_t_;
    PixelPrediction p;
    if (!model_(R, t, Eigen::Map<const Eigen::Vector3d>(point), jacobians != nullptr, &p))
      return false;
    Eigen::Map<Eigen::Vector2d> r(residuals);
    r = weight_ * (p.pixel - observed_);
    if (!jacobians) return true;
    if (pose && jacobians[0]) {
      Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J(jacobians[0]);
      J = weight_ * in_block<2>(p.pose, pose);
    }
    if (double* point_jacobian = jacobians[fixed_t_ ? 0 : 1]) {
      Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J(point_jacobian);
      J = weight_ * p.point;
    }
    return true;
  }

 private:
  PixelModel model_;
  const Eigen::Matrix3d* R_ref_;
  const Eigen::Vector3d* fixed_t_;
  Eigen::Vector2d observed_;
  double weight_;
};

// The motion prior between consecutive poses (motion_prior_residual.h), its prediction moved by
// the sensors' states: e - C (prior + offset - predicted_at), whitened by the motion's weight W.
// Blocks: the previous pose (unless it is the window's first), the pose, the sensors' offset.
class StartMotionCost : public ceres::CostFunction {
 public:
  struct Frame {
    const Eigen::Matrix3d* R_ref;
    const Eigen::Vector3d* fixed_t;  // the window's first pose, else null
  };
  StartMotionCost(Frame previous, Frame current, const MotionPrediction* motion,
                  const Eigen::Matrix<double, 6, 6>& weight,
                  const Eigen::Matrix<double, 6, 4>& sensor_jacobian,
                  const Eigen::Vector4d& prior_minus_predicted)
      : previous_(previous), current_(current), motion_(motion), C_(sensor_jacobian),
        offset_(prior_minus_predicted) {
    U_ = weight.llt().matrixU();  // W = U^T U
    set_num_residuals(6);
    if (!previous_.fixed_t) mutable_parameter_block_sizes()->push_back(6);
    mutable_parameter_block_sizes()->push_back(6);
    mutable_parameter_block_sizes()->push_back(4);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int k = previous_.fixed_t ? 0 : 1;
    const double* p0 = k ? parameters[0] : nullptr;
    const double* p1 = parameters[k];
    const Eigen::Map<const Eigen::Vector4d> sensors(parameters[k + 1]);
    const Eigen::Matrix3d R0 = p0 ? rotation_of(p0, *previous_.R_ref) : *previous_.R_ref;
    const Eigen::Vector3d t0 =
        p0 ? Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(p0 + 3)) : *previous_.fixed_t;
    const MotionPriorResidual r = motion_prior_residual(
        R0, t0, rotation_of(p1, *current_.R_ref), Eigen::Map<const Eigen::Vector3d>(p1 + 3),
        motion_);
    Eigen::Map<Eigen::Matrix<double, 6, 1>> whitened(residuals);
    whitened = U_ * (r.e - C_ * (offset_ + sensors));
    if (!jacobians) return true;
    using Block = Eigen::Matrix<double, 6, 6, Eigen::RowMajor>;
    if (p0 && jacobians[0]) Block::Map(jacobians[0]) = U_ * in_block<6>(r.J_previous, p0);
    if (jacobians[k]) Block::Map(jacobians[k]) = U_ * in_block<6>(r.J_current, p1);
    if (jacobians[k + 1])
      Eigen::Matrix<double, 6, 4, Eigen::RowMajor>::Map(jacobians[k + 1]) = -U_ * C_;
    return true;
  }

 private:
  Frame previous_, current_;
  const MotionPrediction* motion_;  // null: the random walk
  Eigen::Matrix<double, 6, 6> U_;
  Eigen::Matrix<double, 6, 4> C_;
  Eigen::Vector4d offset_;
};

// Vision alone: a camera held at its distance from the first, sigma^-1 (|t| - distance).
class StartScaleCost : public ceres::CostFunction {
 public:
  StartScaleCost(double distance, double sigma) : distance_(distance), weight_(1 / sigma) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(6);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Map<const Eigen::Vector3d> t(parameters[0] + 3);
    residuals[0] = weight_ * (t.norm() - distance_);
    if (jacobians && jacobians[0]) {
      Eigen::Map<PoseBlock> J(jacobians[0]);
      J.head<3>().setZero();
      J.tail<3>() = weight_ * t / t.norm();
    }
    return true;
  }

 private:
  double distance_, weight_;
};

}  // namespace omnisfm::sfm
