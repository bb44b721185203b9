#pragma once
// The batch's residuals from the vehicle's sensors, for Ceres, with analytic Jacobians. Poses are
// the batch's parameter blocks: cam_from_world as (angle-axis, translation). Each residual is
// whitened by its covariance (r = L^-1 e with covariance = L L^T). The caller owns what these
// return.
//
// Odometry between frames k and k+1 (blocks: pose k, pose k+1, odometry scale [1]): the planar
// part (x, y, yaw) of body_k_from_body_k+1 predicted by the poses, with its distances divided by
// the scale s (true distance per distance read), minus the odometry increment.
//   e = (x / s - dx, y / s - dy, wrap(yaw - dyaw))
// It is in what the wheel read, as its noise is: in metres, (x - s dx) would shrink with the
// scene, and the batch would shrink the scene and the scale together to lower it.
//
// Gyro between frames k and k+1 (blocks: pose k, pose k+1, gyro bias [3]): the rotation
// body_k_from_body_k+1 predicted by the poses against the integrated rates with the bias taken
// away, to first order about the integration's bias (frame_motion.h):
//   e = Log( (dR Exp(J_rotation_bias (b - b_lin)))^T R_pred )
//
// GPS at a time between frames k and k+1, alpha of the way (blocks: pose k, pose k+1): the
// antenna's world position, interpolated linearly between its positions at the two frames, minus
// the fix.
//   e = (1 - alpha) a_k + alpha a_k+1 - z,   a_j = world_from_cam_j (cam_from_body antenna_in_body)

#include <Eigen/Geometry>

#include "omnisfm/sfm/frame_motion.h"

namespace ceres {
class CostFunction;
}

namespace omnisfm::sfm {

ceres::CostFunction* make_odometry_cost(const OdometryIncrement& increment,
                                        const Eigen::Isometry3d& body_from_cam);

ceres::CostFunction* make_gyro_cost(const GyroIncrement& increment,
                                    const Eigen::Isometry3d& body_from_cam);

ceres::CostFunction* make_gps_cost(const Eigen::Vector3d& antenna_enu,
                                   const Eigen::Matrix3d& covariance, double alpha,
                                   const Eigen::Vector3d& antenna_in_cam);

}  // namespace omnisfm::sfm
