#pragma once
// The filter's motion model between consecutive poses as a residual, for the smoothed start:
// zero when the pose moved exactly as predicted, distributed as the propagation's noise. Poses
// are cam_from_world (R, t) perturbed as the filter's: R = Exp(dtheta) R, t = t + dt.
//   random walk:       e = ( Log(R1 R0^T), t1 - t0 )
//   predicted motion:  e = ( Log(R1 R0^T R_M^T), t1 - R1 R0^T t0 - t_M ),
// the second the inverse of propagate(motion)'s model R1 = Exp(dm) R_M R0,
// t1 = Exp(dm) R_M t0 + t_M + dt_M.

#include <Eigen/Geometry>

#include "omnisfm/sfm/online_filter.h"
#include "so3.h"

namespace omnisfm::sfm {

struct MotionPriorResidual {
  Eigen::Matrix<double, 6, 1> e;
  Eigen::Matrix<double, 6, 6> J_previous, J_current;  // with respect to (dtheta, dt) of each pose
};

// `motion` null for the random walk.
inline MotionPriorResidual motion_prior_residual(const Eigen::Matrix3d& R0,
                                                 const Eigen::Vector3d& t0,
                                                 const Eigen::Matrix3d& R1,
                                                 const Eigen::Vector3d& t1,
                                                 const MotionPrediction* motion) {
  // Log(Exp(d) E) ~= Log(E) + J_left(e)^-1 d and Log(E Exp(d)) ~= Log(E) + J_right(e)^-1 d,
  // with J_left(e)^-1 = J_right(-e)^-1.
  const Eigen::Matrix3d R_M =
      motion ? Eigen::Matrix3d(motion->cam_from_previous_cam.linear()) : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d relative = R1 * R0.transpose();
  const Eigen::Vector3d e_rotation = so3::log(relative * R_M.transpose());
  MotionPriorResidual r;
  r.e.head<3>() = e_rotation;
  r.J_previous.setZero();
  r.J_current.setZero();
  r.J_current.topLeftCorner<3, 3>() = so3::right_jacobian_inverse(-e_rotation);
  // R0^T -> R0^T Exp(-d): E -> E R_M Exp(-d) R_M^T = E Exp(-R_M d).
  r.J_previous.topLeftCorner<3, 3>() = -so3::right_jacobian_inverse(e_rotation) * R_M;
  if (!motion) {
    r.e.tail<3>() = t1 - t0;
    r.J_current.bottomRightCorner<3, 3>().setIdentity();
    r.J_previous.bottomRightCorner<3, 3>() = -Eigen::Matrix3d::Identity();
    return r;
  }
  const Eigen::Vector3d carried = relative * t0;
  r.e.tail<3>() = t1 - carried - motion->cam_from_previous_cam.translation();
  r.J_current.bottomLeftCorner<3, 3>() = so3::skew(carried);
  r.J_current.bottomRightCorner<3, 3>().setIdentity();
  r.J_previous.bottomLeftCorner<3, 3>() = -relative * so3::skew(t0);
  r.J_previous.bottomRightCorner<3, 3>() = -relative;
  return r;
}

}  // namespace omnisfm::sfm
