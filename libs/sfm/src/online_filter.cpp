#include "omnisfm/sfm/online_filter.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <set>

#include "filter_linear_algebra.h"
#include "so3.h"

namespace omnisfm::sfm {
namespace {

// One kilometre: far enough to stand for infinity in any scene the rig maps.
constexpr double kMinInverseDepth = 1e-3;

}  // namespace

OnlineFilter::OnlineFilter(const camera::CatadioptricCamera& camera, const FilterSettings& settings)
    : camera_(camera), settings_(settings), P_(Eigen::MatrixXd::Zero(6, 6)) {}

Eigen::Isometry3d OnlineFilter::cam_from_world() const {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_;
  T.translation() = t_;
  return T;
}

std::map<int, Eigen::Vector3d> OnlineFilter::points() const {
  std::map<int, Eigen::Vector3d> all = ended_points_;
  for (size_t s = 0; s < slot_track_.size(); ++s)
    all[slot_track_[s]] = world_point(static_cast<int>(s), points_.segment<3>(3 * s));
  return all;
}

Eigen::Vector3d OnlineFilter::world_point(int slot, const Eigen::Vector3d& params,
                                          Eigen::Matrix3d* J_params) const {
  const Anchor& a = anchors_[slot];
  const Eigen::Vector3d u = a.basis.col(0) + params.x() * a.basis.col(1) + params.y() * a.basis.col(2);
  const double norm = u.norm();
  const Eigen::Vector3d direction = u / norm;
  const double rho = params.z();
  if (J_params) {
    const Eigen::Matrix3d across = (Eigen::Matrix3d::Identity() - direction * direction.transpose()) / norm;
    *J_params << across * a.basis.col(1) / rho, across * a.basis.col(2) / rho,
        -direction / (rho * rho);
  }
  return a.origin + direction / rho;
}

void OnlineFilter::propagate() {
  P_.topLeftCorner<3, 3>().diagonal().array() += std::pow(settings_.rotation_walk_sigma, 2);
  P_.block<3, 3>(3, 3).diagonal().array() += std::pow(settings_.translation_walk_sigma, 2);
}

void OnlineFilter::remove_slot(int slot) {
  const int last = static_cast<int>(slot_track_.size()) - 1;
  const int n = 6 + 3 * last;  // size after removal
  if (slot != last) {
    const int from = 6 + 3 * last, to = 6 + 3 * slot;
    points_.segment<3>(3 * slot) = points_.segment<3>(3 * last);
    anchors_[slot] = anchors_[last];
    P_.middleCols<3>(to) = P_.middleCols<3>(from);
    P_.middleRows<3>(to) = P_.middleRows<3>(from);
    slot_track_[slot] = slot_track_[last];
    track_slot_[slot_track_[slot]] = slot;
  }
  slot_track_.pop_back();
  anchors_.pop_back();
  points_.conservativeResize(3 * last);
  P_.conservativeResize(n, n);
}

void OnlineFilter::add_point(int track, const Eigen::Vector2d& pixel) {
  Eigen::Vector3d origin, direction;
  if (!camera_.unproject(pixel, &origin, &direction)) return;
  // Angular resolution at this pixel, for the certainty across the ray.
  Eigen::Vector3d o2, d2;
  double radians_per_pixel = 0.005;
  if (camera_.unproject(pixel + Eigen::Vector2d(1, 0), &o2, &d2))
    radians_per_pixel = std::acos(std::clamp(direction.dot(d2), -1.0, 1.0));

  Anchor anchor;
  anchor.origin = R_.transpose() * (origin - t_);
  const Eigen::Vector3d d_W = R_.transpose() * direction;
  anchor.basis.col(0) = d_W;
  anchor.basis.col(1) = d_W.unitOrthogonal();
  anchor.basis.col(2) = d_W.cross(anchor.basis.col(1));
  const int slot = static_cast<int>(slot_track_.size());
  anchors_.push_back(anchor);
  slot_track_.push_back(track);
  track_slot_[track] = slot;
  const Eigen::Vector3d params(0, 0, 1 / settings_.initial_depth);

  // The point hangs on the current pose: X_W = R^T (X_C - t), with R = exp(dtheta) R, moved into
  // the point's parameters through the inverse of their Jacobian.
  Eigen::Matrix3d J_X_params;
  const Eigen::Vector3d X_W = world_point(slot, params, &J_X_params);
  const Eigen::Vector3d X_C = R_ * X_W + t_;
  Eigen::Matrix<double, 3, 6> J_pose;
  J_pose << R_.transpose() * so3::skew(X_C - t_), -R_.transpose();
  const Eigen::Matrix<double, 3, 6> G = J_X_params.inverse() * J_pose;
  const double across = radians_per_pixel * settings_.pixel_sigma;
  const Eigen::Vector3d own_sigma(across, across, settings_.inverse_depth_sigma);

  const int n = static_cast<int>(P_.rows());
  P_.conservativeResize(n + 3, n + 3);
  const Eigen::MatrixXd cross = G * P_.topLeftCorner(6, n);  // 3 x n
  P_.bottomLeftCorner(3, n) = cross;
  P_.topRightCorner(n, 3) = cross.transpose();
  P_.bottomRightCorner<3, 3>() = G * P_.topLeftCorner<6, 6>() * G.transpose();
  P_.bottomRightCorner<3, 3>().diagonal() += own_sigma.cwiseAbs2();
  points_.conservativeResize(3 * slot + 3);
  points_.segment<3>(3 * slot) = params;
}

bool OnlineFilter::linearise(int slot, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                             const Eigen::Vector3d& params, bool jacobians,
                             Linearisation* out) const {
  if (!(params.z() > 0)) return false;
  Eigen::Matrix3d J_world_params;
  const Eigen::Vector3d RX = R * world_point(slot, params, jacobians ? &J_world_params : nullptr);
  Eigen::Matrix<double, 2, 3> J_X;
  if (!camera_.project(RX + t, &out->pixel, jacobians ? &J_X : nullptr)) return false;
  if (jacobians) {
    out->pose << -J_X * so3::skew(RX), J_X;
    out->point = J_X * R * J_world_params;
  }
  return true;
}

void OnlineFilter::update(const std::vector<Measurement>& meas, Candidate* c) const {
  const int m = static_cast<int>(meas.size());
  const int n = static_cast<int>(P_.rows());
  const double variance = settings_.pixel_sigma * settings_.pixel_sigma;
  c->R = R_;
  c->t = t_;
  c->points = points_;
  c->residuals.resize(m);
  Eigen::VectorXd& X = c->points;
  // H is sparse: each measurement's two rows touch the pose and its own point only. The pose
  // columns of all rows are kept together, for one product with P's pose columns. Each
  // measurement's rows, prediction and innovation z - h(x_i) - H (x_prior - x_i) come from the
  // last iterate x_i where it projected.
  Eigen::Matrix<double, Eigen::Dynamic, 6> H_pose(2 * m, 6);
  std::vector<Eigen::Matrix<double, 2, 3>> H_point(m);
  Eigen::VectorXd predicted(2 * m), innovation(2 * m);
  for (int k = 0; k < m; ++k) {
    H_pose.middleRows<2>(2 * k) = meas[k].at_prior.pose;
    H_point[k] = meas[k].at_prior.point;
    predicted.segment<2>(2 * k) = meas[k].at_prior.pixel;
    innovation.segment<2>(2 * k) = meas[k].pixel - meas[k].at_prior.pixel;
  }
  Eigen::MatrixXd& PHt = c->PHt;
  Eigen::MatrixXd& S = c->S_factor;
  PHt.resize(n, 2 * m);
  S.resize(2 * m, 2 * m);
  const double settled_px = 0.03 * settings_.pixel_sigma;
  const int linearisations = std::max(1, settings_.update_iterations);

  for (int iteration = 0;; ++iteration) {
    // P H^T and S = H P H^T + R from the blocks of H; the Cholesky factorisation reads S's
    // lower triangle only.
    multiply(P_.leftCols<6>(), false, H_pose, true, PHt);
    for (int k = 0; k < m; ++k)
      PHt.middleCols<2>(2 * k).noalias() +=
          P_.middleCols<3>(6 + 3 * meas[k].slot) * H_point[k].transpose();
    multiply(H_pose, false, PHt.topRows<6>(), false, S);
    for (int k = 0; k < m; ++k)
      S.block(2 * k, 0, 2, 2 * k + 2).noalias() +=
          H_point[k] * PHt.block(6 + 3 * meas[k].slot, 0, 3, 2 * k + 2);
    S.diagonal().array() += variance;
    if (!cholesky_lower_in_place(&S)) {
      c->PHt.resize(0, 0);
      return;
    }
    Eigen::VectorXd weighted = S.triangularView<Eigen::Lower>().solve(innovation);
    S.triangularView<Eigen::Lower>().adjoint().solveInPlace(weighted);
    const Eigen::VectorXd correction = PHt * weighted;
    c->R = so3::exp(correction.head<3>()) * R_;
    c->t = t_ + correction.segment<3>(3);
    X = points_ + correction.tail(n - 6);
    // Noise can push a barely-parallaxed point past infinity: hold it far away instead.
    for (int k = 2; k < X.size(); k += 3) X[k] = std::max(X[k], kMinInverseDepth);

    // Project the new iterate (its pixels are the outlier test's residuals). Settled when its
    // predicted pixels moved by less than 3 % of the pixel noise: linearising there again would
    // change nothing measurable, and P H^T and S stay this linearisation's, which the iterate
    // came from.
    const bool may_relinearise = iteration + 1 < linearisations;
    Eigen::Matrix<double, 6, 1> prior_offset;
    prior_offset << so3::log(R_ * c->R.transpose()), t_ - c->t;
    bool settled = true;
    for (int k = 0; k < m; ++k) {
      const int s = meas[k].slot;
      Linearisation at;
      if (!linearise(s, c->R, c->t, X.segment<3>(3 * s), may_relinearise, &at)) {
        // Off the mirror here: its previous linearisation stays, and it fails the outlier test
        // unless a later iterate brings it back.
        c->residuals[k] = INFINITY;
        continue;
      }
      c->residuals[k] = (at.pixel - meas[k].pixel).norm();
      if ((at.pixel - predicted.segment<2>(2 * k)).cwiseAbs().maxCoeff() >= settled_px)
        settled = false;
      if (!may_relinearise) continue;
      H_pose.middleRows<2>(2 * k) = at.pose;
      H_point[k] = at.point;
      predicted.segment<2>(2 * k) = at.pixel;
      innovation.segment<2>(2 * k) = meas[k].pixel - at.pixel - at.pose * prior_offset -
                                     at.point * (points_.segment<3>(3 * s) - X.segment<3>(3 * s));
    }
    if (settled || !may_relinearise) return;
  }
}

void OnlineFilter::accept(Candidate* c) {
  R_ = c->R;
  t_ = c->t;
  points_.swap(c->points);
  downdate_covariance(&P_, &c->PHt, c->S_factor);
}

bool OnlineFilter::process_frame(int frame, const std::vector<TrackPixel>& observations) {
  return process(frame, observations, nullptr);
}

bool OnlineFilter::process(int frame, const std::vector<TrackPixel>& observations,
                           const MotionPrediction* motion) {
  std::map<int, Eigen::Vector2d> seen;
  for (const auto& o : observations)
    if (!excluded_.count(o.track)) seen[o.track] = o.pixel;

  if (!started_) {
    started_ = true;
    for (const auto& [track, pixel] : seen) add_point(track, pixel);
    return true;
  }

  // Tracks not seen in this frame have ended: their points leave the state.
  for (int s = static_cast<int>(slot_track_.size()) - 1; s >= 0; --s)
    if (!seen.count(slot_track_[s])) {
      ended_points_[slot_track_[s]] = world_point(s, points_.segment<3>(3 * s));
      track_slot_.erase(slot_track_[s]);
      remove_slot(s);
    }

  if (motion)
    propagate(*motion);
  else
    propagate();

  std::vector<Measurement> measurements;
  for (const auto& [track, pixel] : seen) {
    const auto slot = track_slot_.find(track);
    if (slot == track_slot_.end()) continue;
    Measurement measurement{slot->second, pixel, {}};
    if (linearise(slot->second, R_, t_, points_.segment<3>(3 * slot->second), true,
                  &measurement.at_prior))
      measurements.push_back(measurement);
  }

  std::set<int> rejected_slots;
  if (settings_.innovation_gate_chi2 > 0) {
    std::vector<Measurement> kept;
    for (const auto& m : measurements) {
      const int c = 6 + 3 * m.slot;
      Eigen::Matrix<double, 2, 9> H;
      H << m.at_prior.pose, m.at_prior.point;
      Eigen::Matrix<double, 9, 9> P_local;
      P_local << P_.topLeftCorner<6, 6>(), P_.block<6, 3>(0, c), P_.block<3, 6>(c, 0),
          P_.block<3, 3>(c, c);
      Eigen::Matrix2d S = H * P_local * H.transpose();
      S.diagonal().array() += settings_.pixel_sigma * settings_.pixel_sigma;
      const Eigen::Vector2d y = m.pixel - m.at_prior.pixel;
      if (y.dot(S.ldlt().solve(y)) > settings_.innovation_gate_chi2)
        rejected_slots.insert(m.slot);
      else
        kept.push_back(m);
    }
    measurements.swap(kept);
  }

  bool updated = false;
  Candidate candidate;
  while (!measurements.empty()) {
    update(measurements, &candidate);
    const auto worst = std::max_element(candidate.residuals.begin(), candidate.residuals.end());
    if (!(*worst <= settings_.outlier_threshold_px)) {
      // The paper's rejection: drop the worst track, redo the update from the prediction.
      const auto index = worst - candidate.residuals.begin();
      rejected_slots.insert(measurements[index].slot);
      measurements.erase(measurements.begin() + index);
      continue;
    }
    accept(&candidate);
    updated = true;
    break;
  }
  // Rejected tracks leave the state for good (highest slot first: removal moves the last slot).
  for (auto it = rejected_slots.rbegin(); it != rejected_slots.rend(); ++it) {
    const int track = slot_track_[*it];
    excluded_[track] = true;
    rejected_.push_back({track, frame});
    track_slot_.erase(track);
    remove_slot(*it);
  }

  for (const auto& [track, pixel] : seen)
    if (!track_slot_.count(track) && !excluded_.count(track)) add_point(track, pixel);
  return updated;
}

}  // namespace omnisfm::sfm
