#include "omnisfm/sfm/filter_state.h"

#include <algorithm>
#include <vector>

#include "so3.h"

namespace omnisfm::sfm {
namespace {

// A pose's error (x, y: the rotation's left perturbation, then the translation's) as it becomes
// when its frame changes by an error (dpsi, dtau) of its own, the frame's rotation becoming
// `turn` and the pose's position seen from it `lever`:
//   x' = x - turn dpsi,  y' = y + [lever]x x' - turn dtau,
// that is (x', y') = own (x, y) + frame (dpsi, dtau).
struct FrameChange {
  Eigen::Matrix<double, 6, 6> own, frame;
};

FrameChange frame_change(const Eigen::Matrix3d& turn, const Eigen::Vector3d& lever) {
  FrameChange c;
  c.own.setIdentity();
  c.own.bottomLeftCorner<3, 3>() = so3::skew(lever);
  c.frame.setZero();
  c.frame.topLeftCorner<3, 3>() = -turn;
  c.frame.bottomLeftCorner<3, 3>() = -so3::skew(lever) * turn;
  c.frame.bottomRightCorner<3, 3>() = -turn;
  return c;
}

}  // namespace

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
  if (wheel_scale_considered()) P(kScaleColumn, kScaleColumn) = wheel_scale_variance_;
}

void FilterState::consider_wheel_scale(double variance) {
  wheel_scale_variance_ = variance;
  reset_considered_blocks();
}

std::vector<int> FilterState::considered_columns() const {
  std::vector<int> columns;
  if (wheel_scale_considered()) columns.push_back(kScaleColumn);
  for (int k = 0; k < 6; ++k) columns.push_back(kOriginColumn + k);
  for (int k = 0; k < num_camera_params(); ++k) columns.push_back(kCameraColumn + k);
  return columns;
}

Eigen::MatrixXd FilterState::considered_covariance() const {
  const std::vector<int> columns = considered_columns();
  return P(columns, columns);
}

void FilterState::restore_considered_covariance(const Eigen::MatrixXd& block) {
  const std::vector<int> columns = considered_columns();
  P(columns, columns) = block;
}

void FilterState::hold_considered(Eigen::VectorXd* step) const {
  step->segment(kCameraColumn, num_camera_params()).setZero();
  step->segment<6>(kOriginColumn).setZero();
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

void FilterState::move_origin_to_camera(bool position_only) {
  // The new frame is N = (Rm, tm) N_from_S of the old, the camera's frame (the pose itself) or
  // the old frame moved to the camera's position c = -R^T t. Its error (dpsi, dtau), Rm =
  // exp(dpsi) Rm, is L times the pose's (dtheta, dt): the identity, or for the position alone
  // dpsi = 0 and dtau = -dc = [R^T [t]x, R^T] (dtheta, dt). Each block of the state then moves
  // by its own error times A plus the pose's times B (P <- J P J^T, rows then columns):
  // - a point's ray, origin a' = Rm a + tm and direction d' = Rm d: its offset turns with Rm,
  //   and the ray moves by -[Rm a]x dpsi + dtau and turns by -[d']x dpsi;
  // - the frame in the world, world_from_N = world_from_S N_from_S^-1 = (Q Rm^T, o - Q' tm):
  //   dphi' = dphi - Q' dpsi, do' = do + [Q' tm]x dphi' - Q' dtau;
  // - the pose, cam_from_N = (R Rm^T, t - R' tm): dtheta' = dtheta - R' dpsi,
  //   dt' = dt + [R' tm]x dtheta' - R' dtau, nothing when N is the camera's frame.
  const Eigen::Matrix3d R = mean.R;
  const Eigen::Vector3d t = mean.t;
  Eigen::Matrix3d Rm = R;
  Eigen::Vector3d tm = t;
  Eigen::Matrix<double, 6, 6> L = Eigen::Matrix<double, 6, 6>::Identity();
  if (position_only) {
    Rm.setIdentity();
    tm = R.transpose() * t;
    L.setZero();
    L.bottomLeftCorner<3, 3>() = R.transpose() * so3::skew(t);
    L.bottomRightCorner<3, 3>() = R.transpose();
  }
  const Eigen::Matrix3d R_new = R * Rm.transpose();
  const Eigen::Matrix3d Q_new = world_from_state_.linear() * Rm.transpose();
  // The frame's error is L times the pose's.
  const FrameChange origin = frame_change(Q_new, Q_new * tm);
  const FrameChange pose = frame_change(R_new, R_new * tm);
  const Eigen::Matrix<double, 6, 6> K_pose = pose.own + pose.frame * L;  // the pose's rows

  struct BlockMove {
    int column;
    Eigen::Matrix<double, 6, 6> A, B;
  };
  std::vector<BlockMove> moves;
  moves.push_back({kOriginColumn, origin.own, origin.frame * L});
  for (int s = 0; s < num_slots(); ++s) {
    PointAnchor& anchor = anchors_[s];
    const PointParams params = mean.params(s);
    const Eigen::Vector3d ray_origin = anchor.origin + params.tail<3>();
    const Eigen::Vector3d u =
        anchor.basis.col(0) + params[0] * anchor.basis.col(1) + params[1] * anchor.basis.col(2);
    anchor.origin = Rm * anchor.origin + tm;
    anchor.basis = Rm * anchor.basis;
    mean.points.segment<3>(kPointSize * s + 3) = Rm * params.tail<3>();
    // The angles that turn the ray's direction as dpsi does, through the direction's Jacobian
    // in them (PointAnchor::world_point), exactly also where they are not zero.
    const Eigen::Vector3d d = Rm * u.normalized();
    const Eigen::Matrix3d across = (Eigen::Matrix3d::Identity() - d * d.transpose()) / u.norm();
    Eigen::Matrix<double, 3, 2> J_angles;
    J_angles << across * anchor.basis.col(1), across * anchor.basis.col(2);
    BlockMove move{point_column(s), Eigen::Matrix<double, 6, 6>::Identity(),
                   Eigen::Matrix<double, 6, 6>::Zero()};
    move.B.topLeftCorner<2, 3>() =
        (J_angles.transpose() * J_angles).ldlt().solve(J_angles.transpose() * -so3::skew(d));
    move.B.bottomLeftCorner<3, 3>() = -so3::skew(Rm * ray_origin);
    move.B.bottomRightCorner<3, 3>().setIdentity();
    move.B = (move.B * L).eval();
    move.A.bottomRightCorner<3, 3>() = Rm;
    moves.push_back(move);
  }
  const Eigen::MatrixXd pose_rows = P.topRows<6>();
  for (const BlockMove& m : moves)
    P.middleRows<6>(m.column) = m.A * P.middleRows<6>(m.column) + m.B * pose_rows;
  P.topRows<6>() = K_pose * pose_rows;
  const Eigen::MatrixXd pose_columns = P.leftCols<6>();
  for (const BlockMove& m : moves)
    P.middleCols<6>(m.column) = P.middleCols<6>(m.column) * m.A.transpose() +
                                pose_columns * m.B.transpose();
  P.leftCols<6>() = pose_columns * K_pose.transpose();
  const int known = position_only ? 3 : 6;  // the translation, or the whole pose, now exact
  P.middleRows(6 - known, known).setZero();
  P.middleCols(6 - known, known).setZero();

  Eigen::Isometry3d new_from_old = Eigen::Isometry3d::Identity();
  new_from_old.linear() = Rm;
  new_from_old.translation() = tm;
  world_from_state_ = world_from_state_ * new_from_old.inverse();
  mean.R = position_only ? R : Eigen::Matrix3d::Identity().eval();
  mean.t.setZero();
}

Eigen::Isometry3d FilterState::world_cam_from_world() const {
  return mean.cam_from_world() * world_from_state_.inverse();
}

Eigen::Matrix<double, 6, 6> FilterState::world_pose_covariance() const {
  // cam_from_world = (R Q^T, t - R_w o): dtheta_w = dtheta - R_w dphi,
  // dt_w = dt + [R_w o]x dtheta_w - R_w do.
  Eigen::Matrix<double, 12, 12> pose_and_origin;
  pose_and_origin << P.topLeftCorner<6, 6>(), P.block<6, 6>(0, kOriginColumn),
      P.block<6, 6>(kOriginColumn, 0), P.block<6, 6>(kOriginColumn, kOriginColumn);
  const Eigen::Matrix3d R_w = mean.R * world_from_state_.linear().transpose();
  const FrameChange to_world = frame_change(R_w, R_w * world_from_state_.translation());
  Eigen::Matrix<double, 6, 12> J;
  J << to_world.own, to_world.frame;
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
  const Eigen::MatrixXd considered = considered_covariance();
  P.noalias() += weight * Pe * Pe.transpose();
  restore_considered_covariance(considered);
  return true;
}

}  // namespace omnisfm::sfm
