#include "omnisfm/sfm/filter_state.h"

#include <algorithm>

#include "so3.h"

namespace omnisfm::sfm {

Eigen::Vector3d PointAnchor::world_point(const PointParams& params,
                                         PointJacobian* J_params) const {
  const Eigen::Vector3d u = basis.col(0) + params[0] * basis.col(1) + params[1] * basis.col(2);
  const double norm = u.norm();
  const Eigen::Vector3d direction = u / norm;
  const double rho = params[2];
  if (J_params) {
    const Eigen::Matrix3d across =
        (Eigen::Matrix3d::Identity() - direction * direction.transpose()) / norm;
    *J_params << across * basis.col(1) / rho, across * basis.col(2) / rho,
        -direction / (rho * rho), Eigen::Matrix3d::Identity();
  }
  return origin + params.tail<3>() + direction / rho;
}

PointParams PointAnchor::params_of(const Eigen::Vector3d& X) const {
  const Eigen::Vector3d ray = X - origin;
  const double along = basis.col(0).dot(ray);
  PointParams params;
  params << basis.col(1).dot(ray) / along, basis.col(2).dot(ray) / along, 1 / ray.norm(), 0, 0, 0;
  return params;
}

Eigen::Matrix<double, 6, Eigen::Dynamic> ray_parameters_jacobian(
    const PointAnchor& anchor, const Eigen::Matrix<double, 3, Eigen::Dynamic>& direction_moves,
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& origin_moves) {
  Eigen::Matrix<double, 6, Eigen::Dynamic> J =
      Eigen::Matrix<double, 6, Eigen::Dynamic>::Zero(6, direction_moves.cols());
  J.row(0) = anchor.basis.col(1).transpose() * direction_moves;
  J.row(1) = anchor.basis.col(2).transpose() * direction_moves;
  J.bottomRows<3>() = origin_moves;
  return J;
}

Eigen::Matrix<double, 6, 6> ray_pose_jacobian(const PointAnchor& anchor, const Eigen::Matrix3d& R,
                                              const Eigen::Vector3d& t,
                                              const Eigen::Vector3d& origin,
                                              const Eigen::Vector3d& direction) {
  // R^T d and R^T (o - t) with R = exp(dtheta) R: each turns by R^T [.]x dtheta.
  Eigen::Matrix<double, 3, 6> direction_moves = Eigen::Matrix<double, 3, 6>::Zero();
  direction_moves.leftCols<3>() = R.transpose() * so3::skew(direction);
  Eigen::Matrix<double, 3, 6> origin_moves;
  origin_moves << R.transpose() * so3::skew(origin - t), -R.transpose();
  return ray_parameters_jacobian(anchor, direction_moves, origin_moves);
}

FilterMean FilterMean::plus(const Eigen::VectorXd& delta, double min_inverse_depth) const {
  FilterMean moved;
  moved.R = so3::exp(delta.head<3>()) * R;
  moved.t = t + delta.segment<3>(3);
  moved.sensors = sensors;
  moved.sensors.gyro_bias += delta.segment<3>(FilterState::kBiasColumn);
  moved.sensors.wheel_scale += delta[FilterState::kScaleColumn];
  moved.points = points + delta.tail(points.size());
  for (Eigen::Index k = 2; k < moved.points.size(); k += FilterState::kPointSize)
    moved.points[k] = std::max(moved.points[k], min_inverse_depth);
  return moved;
}

PointParams FilterMean::params(int slot) const {
  return points.segment<FilterState::kPointSize>(FilterState::kPointSize * slot);
}

Eigen::Isometry3d FilterMean::cam_from_world() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = t;
  return T;
}

FilterState::FilterState(const Eigen::MatrixXd& camera_covariance)
    : P(Eigen::MatrixXd::Zero(kCameraColumn + camera_covariance.rows(),
                              kCameraColumn + camera_covariance.rows())),
      camera_covariance_(camera_covariance) {
  reset_considered_blocks();
}

void FilterState::reset_considered_blocks() {
  const int k = num_camera_params();
  P.block(kCameraColumn, kCameraColumn, k, k) = camera_covariance_;
  P.block<3, 3>(kOriginColumn, kOriginColumn) = origin_covariance_;
  if (wheel_scale_considered()) P(kScaleColumn, kScaleColumn) = wheel_scale_variance_;
}

void FilterState::consider_wheel_scale(double variance) {
  wheel_scale_variance_ = variance;
  reset_considered_blocks();
}

void FilterState::hold_considered(Eigen::VectorXd* step) const {
  step->segment(kCameraColumn, num_camera_params()).setZero();
  step->segment<3>(kOriginColumn).setZero();
  if (wheel_scale_considered()) (*step)[kScaleColumn] = 0;
}

int FilterState::slot_of(int track) const {
  const auto slot = track_slot_.find(track);
  return slot == track_slot_.end() ? -1 : slot->second;
}

int FilterState::add(int track, const PointAnchor& anchor, const PointParams& params,
                     const Eigen::Matrix<double, kPointSize, 6>& G, const PointParams& own_sigma,
                     const Eigen::MatrixXd& G_camera) {
  constexpr int k = kPointSize;
  const int slot = num_slots();
  anchors_.push_back(anchor);
  slot_track_.push_back(track);
  track_slot_[track] = slot;
  const int n = static_cast<int>(P.rows());
  const int c = num_camera_params();
  P.conservativeResize(n + k, n + k);
  // With J = [G, G_camera] on the pose's and the camera's columns: the cross-covariance J P[those
  // rows, :], and J P[those, those] J^T.
  Eigen::MatrixXd cross = G * P.topLeftCorner(6, n);  // k x n
  if (c > 0) cross.noalias() += G_camera * P.block(kCameraColumn, 0, c, n);
  P.bottomLeftCorner(k, n) = cross;
  P.topRightCorner(n, k) = cross.transpose();
  P.bottomRightCorner<k, k>() = G * P.topLeftCorner<6, 6>() * G.transpose();
  if (c > 0) {
    // + G P_pc Gc^T + Gc P_cp G^T + Gc P_cc Gc^T, the first and last from the cross-covariance.
    const Eigen::MatrixXd pose_camera = G * P.block(0, kCameraColumn, 6, c) * G_camera.transpose();
    P.bottomRightCorner<k, k>() +=
        cross.middleCols(kCameraColumn, c) * G_camera.transpose() + pose_camera.transpose();
  }
  P.bottomRightCorner<k, k>().diagonal() += own_sigma.cwiseAbs2();
  mean.points.conservativeResize(k * slot + k);
  mean.points.segment<k>(k * slot) = params;
  return slot;
}

void FilterState::remove(int slot) {
  track_slot_.erase(slot_track_[slot]);
  const int last = num_slots() - 1;
  const int n = point_column(last);  // size after removal
  if (slot != last) {
    const int from = point_column(last), to = point_column(slot);
    mean.points.segment<kPointSize>(kPointSize * slot) =
        mean.points.segment<kPointSize>(kPointSize * last);
    anchors_[slot] = anchors_[last];
    P.middleCols<kPointSize>(to) = P.middleCols<kPointSize>(from);
    P.middleRows<kPointSize>(to) = P.middleRows<kPointSize>(from);
    slot_track_[slot] = slot_track_[last];
    track_slot_[slot_track_[slot]] = slot;
  }
  slot_track_.pop_back();
  anchors_.pop_back();
  mean.points.conservativeResize(kPointSize * last);
  P.conservativeResize(n, n);
}

void FilterState::move_origin_to_camera() {
  // The camera's position c = -R^T t; with R = exp(dtheta) R its error is
  // dc = -R^T [t]x dtheta - R^T dt = -M (dtheta, dt). The new origin's error is the old one's
  // plus dc, and each point's error relative to it is its own minus dc: the origin's rows gain
  // -M times the pose's, each anchor's offset rows M times, and the translation's rows go
  // (P <- J P J^T, rows then columns).
  const Eigen::Matrix3d Rt = mean.R.transpose();
  Eigen::Matrix<double, 3, 6> M;
  M << Rt * so3::skew(mean.t), Rt;
  const Eigen::Vector3d shift = -Rt * mean.t;
  const Eigen::MatrixXd pose_rows = P.topRows<6>();
  P.middleRows<3>(kOriginColumn).noalias() -= M * pose_rows;
  for (int s = 0; s < num_slots(); ++s)
    P.middleRows<3>(point_column(s) + 3).noalias() += M * pose_rows;
  const Eigen::MatrixXd pose_columns = P.leftCols<6>();
  P.middleCols<3>(kOriginColumn).noalias() -= pose_columns * M.transpose();
  for (int s = 0; s < num_slots(); ++s)
    P.middleCols<3>(point_column(s) + 3).noalias() += pose_columns * M.transpose();
  P.middleRows<3>(3).setZero();
  P.middleCols<3>(3).setZero();
  origin_covariance_ = P.block<3, 3>(kOriginColumn, kOriginColumn);
  for (PointAnchor& anchor : anchors_) anchor.origin -= shift;
  mean.t.setZero();
  origin_ += shift;
}

Eigen::Isometry3d FilterState::world_cam_from_world() const {
  Eigen::Isometry3d cam_from_world = mean.cam_from_world();
  cam_from_world.translation() -= mean.R * origin_;
  return cam_from_world;
}

Eigen::Matrix<double, 6, 6> FilterState::world_pose_covariance() const {
  // t_world = t - R o: with R = exp(dtheta) R, dt_world = dt + [R o]x dtheta - R do.
  Eigen::Matrix<double, 9, 9> pose_and_origin;
  pose_and_origin << P.topLeftCorner<6, 6>(), P.block<6, 3>(0, kOriginColumn),
      P.block<3, 6>(kOriginColumn, 0), P.block<3, 3>(kOriginColumn, kOriginColumn);
  Eigen::Matrix<double, 6, 9> J = Eigen::Matrix<double, 6, 9>::Zero();
  J.leftCols<6>().setIdentity();
  J.block<3, 3>(3, 0) = so3::skew(mean.R * origin_);
  J.block<3, 3>(3, 6) = -mean.R;
  return J * pose_and_origin * J.transpose();
}

bool FilterState::take_back_prior(int column, double prior_mean, double prior_variance,
                                  double min_inverse_depth) {
  if (!(P(column, column) < prior_variance)) return false;
  // With v = P(c, c): P' = P + P e e^T P / (prior_variance - v),
  // x' = x + P e (x_c - prior_mean) / (prior_variance - v).
  const double weight = 1 / (prior_variance - P(column, column));
  const Eigen::VectorXd Pe = P.col(column);
  const double value = mean.points[column - first_point_column()];
  Eigen::VectorXd step = Pe * (weight * (value - prior_mean));
  hold_considered(&step);
  mean = mean.plus(step, min_inverse_depth);
  P.noalias() += weight * Pe * Pe.transpose();
  reset_considered_blocks();
  return true;
}

}  // namespace omnisfm::sfm
