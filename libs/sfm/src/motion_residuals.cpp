#include "omnisfm/sfm/motion_residuals.h"

#include <ceres/ceres.h>

#include "so3.h"

namespace omnisfm::sfm {
namespace {

using RowMajor36 = Eigen::Matrix<double, 3, 6, Eigen::RowMajor>;

// A pose block's rotation, translation and the left Jacobian of its angle-axis:
// R(aa + d) ~= Exp(J_left d) R(aa).
struct PoseBlock {
  explicit PoseBlock(const double* p) : aa(p), t(p + 3) {
    R = so3::exp(aa);
    J_left = so3::left_jacobian(aa);
  }
  Eigen::Map<const Eigen::Vector3d> aa, t;
  Eigen::Matrix3d R, J_left;
};

// The whitening of a covariance: W with W^T W = covariance^-1.
Eigen::Matrix3d whitening(const Eigen::Matrix3d& covariance) {
  const Eigen::Matrix3d L = covariance.llt().matrixL();
  return L.inverse();
}

// Writes W [J_rotation * J_left, J_translation] into a pose block's Jacobian, when asked for.
void write_pose_jacobian(double* out, const Eigen::Matrix3d& W, const Eigen::Matrix3d& J_rotation,
                         const Eigen::Matrix3d& J_translation, const PoseBlock& pose) {
  if (!out) return;
  Eigen::Map<RowMajor36> J(out);
  J << W * J_rotation * pose.J_left, W * J_translation;
}

class OdometryCost : public ceres::SizedCostFunction<3, 6, 6, 1> {
 public:
  OdometryCost(const OdometryIncrement& increment, const Eigen::Isometry3d& body_from_cam)
      : delta_(increment.delta),
        W_(whitening(increment.covariance)),
        R_bc_(body_from_cam.linear()),
        p_bc_(body_from_cam.translation()),
        p_cb_(body_from_cam.inverse().translation()) {}

  // body_k_from_body_k+1 = T_bc T_ck_from_ck+1 T_cb, with A = R_k R_k+1^T:
  //   Q = R_bc A R_cb,   tau = R_bc (A (p_cb - t_k+1) + t_k) + p_bc.
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const PoseBlock k(parameters[0]), next(parameters[1]);
    const double scale = parameters[2][0];
    const Eigen::Matrix3d A = k.R * next.R.transpose();
    const Eigen::Matrix3d Q = R_bc_ * A * R_bc_.transpose();
    const Eigen::Vector3d u = p_cb_ - next.t;
    const Eigen::Vector3d tau = R_bc_ * (A * u + k.t) + p_bc_;
    const double yaw = std::atan2(Q(1, 0), Q(0, 0));
    const double inverse_scale = 1 / scale;
    const Eigen::Vector3d e(inverse_scale * tau.x() - delta_.x(), inverse_scale * tau.y() - delta_.y(),
                            wrap_angle(yaw - delta_.z()));
    Eigen::Vector3d::Map(residuals) = W_ * e;
    if (!jacobians) return true;

    // yaw = atan2(Q10, Q00): its gradient with respect to Q's first column.
    const Eigen::RowVector3d g =
        Eigen::RowVector3d(-Q(1, 0), Q(0, 0), 0) / (Q(0, 0) * Q(0, 0) + Q(1, 0) * Q(1, 0));
    // Left perturbations: R_k -> Exp(phi) R_k turns Q into Exp(R_bc phi) Q; R_k+1 -> Exp(phi) R_k+1
    // turns it into Q Exp(-R_bc phi).
    Eigen::Matrix3d J_phi_k, J_phi_next, J_t_k = Eigen::Matrix3d::Zero(), J_t_next = Eigen::Matrix3d::Zero();
    J_phi_k.topRows<2>() = (-R_bc_ * so3::skew(A * u)).topRows<2>();
    J_phi_k.row(2) = g * -so3::skew(Q.col(0)) * R_bc_;
    J_phi_next.topRows<2>() = (R_bc_ * A * so3::skew(u)).topRows<2>();
    J_phi_next.row(2) = g * Q * so3::skew(Eigen::Vector3d::UnitX()) * R_bc_;
    J_t_k.topRows<2>() = R_bc_.topRows<2>();
    J_t_next.topRows<2>() = (-R_bc_ * A).topRows<2>();
    for (Eigen::Matrix3d* J : {&J_phi_k, &J_phi_next, &J_t_k, &J_t_next}) J->topRows<2>() *= inverse_scale;
    write_pose_jacobian(jacobians[0], W_, J_phi_k, J_t_k, k);
    write_pose_jacobian(jacobians[1], W_, J_phi_next, J_t_next, next);
    if (jacobians[2])
      Eigen::Vector3d::Map(jacobians[2]) =
          W_ * Eigen::Vector3d(-tau.x(), -tau.y(), 0) * (inverse_scale * inverse_scale);
    return true;
  }

 private:
  Eigen::Vector3d delta_;
  Eigen::Matrix3d W_, R_bc_;
  Eigen::Vector3d p_bc_, p_cb_;
};

class GyroCost : public ceres::SizedCostFunction<3, 6, 6, 3> {
 public:
  GyroCost(const GyroIncrement& increment, const Eigen::Isometry3d& body_from_cam)
      : increment_(increment), W_(whitening(increment.covariance)), R_bc_(body_from_cam.linear()) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const PoseBlock k(parameters[0]), next(parameters[1]);
    const Eigen::Map<const Eigen::Vector3d> bias(parameters[2]);
    const Eigen::Matrix3d Q = R_bc_ * k.R * next.R.transpose() * R_bc_.transpose();
    const Eigen::Vector3d bias_angle = increment_.J_rotation_bias * (bias - increment_.bias_lin);
    const Eigen::Matrix3d measured = increment_.rotation * so3::exp(bias_angle);
    const Eigen::Matrix3d E = measured.transpose() * Q;
    const Eigen::Vector3d r = so3::log(E);
    Eigen::Vector3d::Map(residuals) = W_ * r;
    if (!jacobians) return true;

    // E Exp(d) ~ Log(E) + Jr^-1 d. R_k's left perturbation phi: E Exp(Q^T R_bc phi); R_k+1's:
    // E Exp(-R_bc phi); the bias's db: Exp(-Jr(bias_angle) J_b db) E = E Exp(-E^T Jr J_b db).
    const Eigen::Matrix3d J_log = so3::right_jacobian_inverse(r);
    write_pose_jacobian(jacobians[0], W_, J_log * Q.transpose() * R_bc_, Eigen::Matrix3d::Zero(), k);
    write_pose_jacobian(jacobians[1], W_, -J_log * R_bc_, Eigen::Matrix3d::Zero(), next);
    if (jacobians[2]) {
      Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> J_bias(jacobians[2]);
      J_bias = -W_ * J_log * E.transpose() * so3::right_jacobian(bias_angle) *
               increment_.J_rotation_bias;
    }
    return true;
  }

 private:
  GyroIncrement increment_;
  Eigen::Matrix3d W_, R_bc_;
};

class GpsCost : public ceres::SizedCostFunction<3, 6, 6> {
 public:
  GpsCost(const Eigen::Vector3d& antenna_enu, const Eigen::Matrix3d& covariance, double alpha,
          const Eigen::Vector3d& antenna_in_cam)
      : fix_(antenna_enu), W_(whitening(covariance)), alpha_(alpha), antenna_in_cam_(antenna_in_cam) {}

  // a_j = R_j^T (c - t_j); R_j -> Exp(phi) R_j moves it by R_j^T [c - t_j]x phi.
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const PoseBlock k(parameters[0]), next(parameters[1]);
    const Eigen::Vector3d w_k = antenna_in_cam_ - k.t, w_next = antenna_in_cam_ - next.t;
    const Eigen::Vector3d antenna =
        (1 - alpha_) * k.R.transpose() * w_k + alpha_ * next.R.transpose() * w_next;
    Eigen::Vector3d::Map(residuals) = W_ * (antenna - fix_);
    if (!jacobians) return true;
    write_pose_jacobian(jacobians[0], W_, (1 - alpha_) * k.R.transpose() * so3::skew(w_k),
                        -(1 - alpha_) * k.R.transpose(), k);
    write_pose_jacobian(jacobians[1], W_, alpha_ * next.R.transpose() * so3::skew(w_next),
                        -alpha_ * next.R.transpose(), next);
    return true;
  }

 private:
  Eigen::Vector3d fix_;
  Eigen::Matrix3d W_;
  double alpha_;
  Eigen::Vector3d antenna_in_cam_;
};

}  // namespace

ceres::CostFunction* make_odometry_cost(const OdometryIncrement& increment,
                                        const Eigen::Isometry3d& body_from_cam) {
  return new OdometryCost(increment, body_from_cam);
}

ceres::CostFunction* make_gyro_cost(const GyroIncrement& increment,
                                    const Eigen::Isometry3d& body_from_cam) {
  return new GyroCost(increment, body_from_cam);
}

ceres::CostFunction* make_gps_cost(const Eigen::Vector3d& antenna_enu,
                                   const Eigen::Matrix3d& covariance, double alpha,
                                   const Eigen::Vector3d& antenna_in_cam) {
  return new GpsCost(antenna_enu, covariance, alpha, antenna_in_cam);
}

}  // namespace omnisfm::sfm
