#include "omnisfm/sfm/online_filter.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "filter_linear_algebra.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/sfm/settings_ranges.h"
#include "so3.h"

namespace omnisfm::sfm {

double FilterSettings::residual_limit_px() const {
  return outlier_test == OutlierTest::kPixels ? outlier_threshold_px
                                              : std::sqrt(outlier_chi2) * pixel_sigma;
}

namespace {

// How much further than the camera's valid patch the filter predicts pixels, as a fraction of its
// width (OnlineFilter::prediction_camera_).
constexpr double kPredictionPatchMargin = 0.05;

// Updates after which a point's depth counts as established (see update()).
constexpr int kEstablishedUpdates = 2;
// Fewer established points than this do not judge a predicted motion (OnlineFilter::
// on_motion_refused): a handful of mistracks could outvote the sensors.
constexpr int kMinPointsToJudgeMotion = 8;
// The outlier scores the noise is measured over (FilterSettings::measure_noise), and how many it
// needs first.
constexpr std::size_t kNoiseWindow = 400;
constexpr std::size_t kMinScoresForNoise = 30;
// The variance over the stated one beyond which the measured noise is taken, below which it is
// let go (OnlineFilter::kMaxNoiseScale bounds the noise taken).
constexpr double kTakeNoiseRatio = 2;
constexpr double kLetGoNoiseRatio = 1.5;

}  // namespace

namespace {

// The considered parameters' covariance, once checked: the state is sized by it.
const Eigen::MatrixXd& checked_uncertainty(const camera::CatadioptricCamera& camera,
                                           const CameraPrior& uncertainty) {
  if (const std::string wrong = camera_prior_problem(camera, uncertainty); !wrong.empty())
    throw std::invalid_argument("FilterSettings::camera_uncertainty: " + wrong);
  return uncertainty.covariance;
}

// Whether the state's frame takes the camera's orientation as it moves
// (FilterSettings::origin_turns_with_camera), in a frame whose whole motion the sensors measured
// or not.
bool turns_with_camera(const FilterSettings& settings, bool with_sensors) {
  const OriginTurnsWithCamera turns = settings.origin_turns_with_camera;
  return turns == OriginTurnsWithCamera::kAlways ||
         (turns == OriginTurnsWithCamera::kWithSensors && with_sensors);
}

}  // namespace

OnlineFilter::OnlineFilter(const camera::CatadioptricCamera& camera, const FilterSettings& settings)
    : camera_(camera),
      prediction_camera_(camera.with_wider_patch(kPredictionPatchMargin)),
      settings_(settings),
      state_(checked_uncertainty(camera, settings.camera_uncertainty)),
      smoothing_start_(settings.smoothed_start_frames > 0) {
  if (const std::string problem = settings_problem(settings); !problem.empty())
    throw std::invalid_argument("FilterSettings: " + problem);
}

std::map<int, Eigen::Vector3d> OnlineFilter::points() const {
  std::map<int, Eigen::Vector3d> all;
  const std::size_t n = history_.size();
  // Oldest first, so that a track that ended twice keeps its latest point.
  for (std::size_t k = 0; k < n; ++k) {
    const EndedPoint& e = history_[(history_next_ + k) % n];
    if (!e.rejected) all[e.track] = e.point;
  }
  for (const auto& [track, point] : held_points_) all[track] = point;
  for (int s = 0; s < state_.num_slots(); ++s)
    if (state_.anchor(s).updates > 0)
      all[state_.track_of(s)] = state_.in_world(state_.world_point(s));
  return all;
}

void OnlineFilter::propagate() {
  state_.P.topLeftCorner<3, 3>().diagonal().array() += std::pow(settings_.rotation_walk_sigma, 2);
  state_.P.block<3, 3>(3, 3).diagonal().array() += std::pow(settings_.translation_walk_sigma, 2);
}

void OnlineFilter::end_point(int slot) {
  const int track = state_.track_of(slot);
  const Eigen::Vector3d point = state_.in_world(state_.world_point(slot));
  // Not while the smoothed start is pending: it solves the window again, priors and all.
  if (settings_.take_back_depth_priors && scale_started_ && !smoothing_start_) {
    const int depth_column = state_.point_column(slot) + 2;
    const double prior_variance = std::pow(settings_.inverse_depth_sigma, 2);
    if (state_.P(depth_column, depth_column) < 0.5 * prior_variance)
      state_.take_back_prior(depth_column, 1 / settings_.initial_depth, prior_variance,
                             kMinInverseDepth);
  }
  // A track seen once has a point made of the depth prior alone: nothing to hand over.
  const bool measured = state_.anchor(slot).updates > 0;
  state_.remove(slot);
  if (!measured) return;
  if (smoothing_start_)
    held_points_[track] = point;  // the smoothed start revises it, then hands it over
  else
    hand_over(track, point);
}

double OnlineFilter::vision_scale_log_sigma() const {
  return distance_measured_ ? 0 : settings_.inverse_depth_sigma * settings_.initial_depth;
}

Eigen::Matrix<double, 6, 6> OnlineFilter::pose_covariance() const {
  Eigen::Matrix<double, 6, 6> covariance = state_.world_pose_covariance();
  const double sigma = vision_scale_log_sigma();
  if (sigma > 0) {
    // The truth is the map scaled by exp(-u), u the log of its scale's error: its translation
    // moves by -t du.
    Eigen::Matrix<double, 6, 1> along_scale = Eigen::Matrix<double, 6, 1>::Zero();
    along_scale.tail<3>() = state_.world_cam_from_world().translation();
    covariance += sigma * sigma * along_scale * along_scale.transpose();
  }
  return covariance;
}

bool OnlineFilter::camera_far_from_origin() const {
  // A fraction of the map's own size: vision alone its scale is the filter's, not metres.
  constexpr double kFractionOfMedianDistance = 0.5;
  const Eigen::Vector3d c = -state_.mean.R.transpose() * state_.mean.t;
  std::vector<double> distances;
  for (int s = 0; s < state_.num_slots(); ++s)
    distances.push_back((state_.world_point(s) - c).norm());
  if (distances.empty()) return false;
  std::nth_element(distances.begin(), distances.begin() + distances.size() / 2, distances.end());
  return c.norm() > kFractionOfMedianDistance * distances[distances.size() / 2];
}

void OnlineFilter::hand_over(int track, const Eigen::Vector3d& point) {
  if (point_ended_) point_ended_(track, point);
  const std::size_t capacity = static_cast<std::size_t>(std::max(settings_.kept_history, 0));
  if (capacity == 0) return;
  if (history_.size() < capacity) {
    history_.push_back({track, false, point});
  } else {
    history_[history_next_] = {track, false, point};
    history_next_ = (history_next_ + 1) % capacity;
  }
}

void OnlineFilter::reject(int track, int frame) {
  excluded_.insert(track);
  const RejectedTrack rejected{track, frame};
  if (track_rejected_) track_rejected_(rejected);
  if (settings_.kept_history > 0) {
    rejected_.push_back(rejected);
    if (static_cast<int>(rejected_.size()) > settings_.kept_history) rejected_.pop_front();
  }
  if (const int slot = state_.slot_of(track); slot >= 0) state_.remove(slot);
  held_points_.erase(track);
  forget_window_track(track);
  for (EndedPoint& e : history_)
    if (e.track == track) e.rejected = true;
}

void OnlineFilter::add_point(int track, const Eigen::Vector2d& pixel) {
  Eigen::Vector3d origin, direction;
  camera::RayJacobian ray;
  const bool considered = state_.num_camera_params() > 0;
  const bool with_jacobian = camera_.unproject(pixel, &origin, &direction, &ray, considered);
  if (!with_jacobian && !camera_.unproject(pixel, &origin, &direction)) return;
  // Angular resolution at this pixel, for the certainty across the ray.
  const double radians_per_pixel = with_jacobian ? ray.direction_pixel.col(0).norm() : 0.005;

  const Eigen::Matrix3d& R = state_.mean.R;
  const Eigen::Vector3d& t = state_.mean.t;
  PointAnchor anchor;
  anchor.origin = R.transpose() * (origin - t);
  const Eigen::Vector3d d_W = R.transpose() * direction;
  anchor.basis.col(0) = d_W;
  anchor.basis.col(1) = d_W.unitOrthogonal();
  anchor.basis.col(2) = d_W.cross(anchor.basis.col(1));
  if (smoothing_start_) start_anchors_[track] = anchor;
  if (window_open_) {
    retire_window_track(track);  // seen before a gap: its earlier sightings are another point's
    window_starts_[track] = {anchor, static_cast<int>(window_frames_.size()) + 1};
  }
  PointParams params = PointParams::Zero();
  params[2] = 1 / settings_.initial_depth;

  // The point hangs on the pose through its anchor (at the given pose in a consistency study).
  Eigen::Matrix3d R_at = R;
  Eigen::Vector3d t_at = t;
  if (at_given_points()) {
    const Eigen::Isometry3d T = linearisation_points_.cam_from_world(frame_);
    R_at = T.linear();
    t_at = T.translation();
  }
  const Eigen::Matrix<double, FilterState::kPointSize, 6> G =
      ray_pose_jacobian(anchor, R_at, t_at, origin, direction);
  const double across = radians_per_pixel * pixel_sigma();
  PointParams own_sigma = PointParams::Zero();
  own_sigma.head<3>() << across, across, settings_.inverse_depth_sigma;
  Eigen::MatrixXd G_camera;  // none without considered parameters
  if (considered)
    G_camera = with_jacobian ? ray_camera_jacobian(anchor, ray, R_at)
                             : Eigen::MatrixXd::Zero(FilterState::kPointSize,
                                                     state_.num_camera_params());
  state_.add(track, anchor, params, G, own_sigma, G_camera);
}

Eigen::MatrixXd OnlineFilter::ray_camera_jacobian(const PointAnchor& anchor,
                                                  const camera::RayJacobian& ray,
                                                  const Eigen::Matrix3d& R) const {
  // The ray's moves in the camera's frame, turned into the world's.
  const std::vector<int>& considered = settings_.camera_uncertainty.parameters;
  const auto k = static_cast<Eigen::Index>(considered.size());
  Eigen::Matrix<double, 3, Eigen::Dynamic> direction_moves(3, k), origin_moves(3, k);
  for (Eigen::Index i = 0; i < k; ++i) {
    direction_moves.col(i) = R.transpose() * ray.direction_params.col(considered[i]);
    origin_moves.col(i) = R.transpose() * ray.origin_params.col(considered[i]);
  }
  return ray_parameters_jacobian(anchor, direction_moves, origin_moves);
}

bool OnlineFilter::linearise(const PointAnchor& anchor, const Eigen::Matrix3d& R,
                             const Eigen::Vector3d& t, const PointParams& params,
                             bool jacobians, Linearisation* out) const {
  if (!(params[2] > 0)) return false;
  PointJacobian J_world_params;
  const Eigen::Vector3d RX = R * anchor.world_point(params, jacobians ? &J_world_params : nullptr);
  Eigen::Matrix<double, 2, 3> J_X;
  const std::vector<int>& considered = settings_.camera_uncertainty.parameters;
  thread_local camera::ParamsJacobian J_params;
  const bool camera_jacobian = jacobians && !considered.empty();
  if (!prediction_camera_.project(RX + t, &out->pixel, jacobians ? &J_X : nullptr,
                                  camera_jacobian ? &J_params : nullptr))
    return false;
  if (jacobians) {
    out->pose << -J_X * so3::skew(RX), J_X;
    out->point = J_X * R * J_world_params;
    out->camera.resize(2, static_cast<Eigen::Index>(considered.size()));
    for (size_t k = 0; k < considered.size(); ++k)
      out->camera.col(static_cast<Eigen::Index>(k)) = J_params.col(considered[k]);
  }
  return true;
}

// The update's first linearisation point. A point that has taken part in fewer than
// kEstablishedUpdates updates knows its depth only from the prior, and its measurement ties that
// depth to the camera's motion since the point entered: a product the linearisation at the prior
// misses, so the first Gauss-Newton steps overshoot and drag the pose along (predicted pixels
// moving tens of pixels between iterates). The first linearisation point is therefore the update
// by the established points alone (the new points' rows of H zero, *warm_step), which places the
// pose; the iterations then start from there. Without new points, the first linearisation point
// is instead the posterior's minimum along the pose's direction of the prior, where one full
// linearisation usually settles. Both only under the random walk, whose prediction says nothing
// of where the camera went. A prediction by the vehicle's sensors is itself a good linearisation
// point, and a point chosen by the measurements it linearises gains information along the scale
// the mirror barely shows (FilterSettings::predicted_settle_sigmas).
OnlineFilter::Iterate OnlineFilter::first_iterate(const std::vector<Measurement>& meas,
                                                  const std::vector<int>& point_columns,
                                                  bool predicted, int linearisations,
                                                  bool* warm_step) const {
  const int m = static_cast<int>(meas.size());
  const int n = static_cast<int>(state_.P.rows());
  const double variance = pixel_sigma() * pixel_sigma();
  Iterate at;
  at.allocate(m, state_.num_camera_params());
  at.offset = Eigen::VectorXd::Zero(n);
  at.g = Eigen::VectorXd::Zero(n);
  at.cost = 0;
  for (int k = 0; k < m; ++k)
    at.cost += at.take(k, meas[k].at_prior, meas[k].pixel, point_columns[k],
                       Eigen::Matrix3d::Identity(), true) /
               variance;
  std::vector<int> new_points;
  for (int k = 0; k < m; ++k)
    if (state_.anchor(meas[k].slot).updates < kEstablishedUpdates) new_points.push_back(k);
  if (!predicted && new_points.empty() && linearisations > 1)
    start_on_pose_subspace(meas, point_columns, &at);
  *warm_step = !predicted && !new_points.empty() && static_cast<int>(new_points.size()) < m &&
               linearisations > 2;
  if (*warm_step)
    for (int k : new_points) {
      at.H_pose.middleRows<2>(2 * k).setZero();
      at.H_point[k].setZero();
      // (Without considered parameters H_camera has no data to offset into.)
      if (at.H_camera.cols() > 0) at.H_camera.middleRows<2>(2 * k).setZero();
    }
  return at;
}

void OnlineFilter::Iterate::allocate(int m, int camera_params) {
  H_pose.resize(2 * m, 6);
  H_camera.resize(2 * m, camera_params);
  H_point.resize(m);
  pixels.resize(2 * m);
  residual.resize(2 * m);
  innovation.resize(2 * m);
  H_offset.resize(2 * m);
}

void OnlineFilter::update(const std::vector<Measurement>& meas, LinearisedAt linearised_at,
                          Candidate* c) const {
  const bool predicted = linearised_at == LinearisedAt::kPrediction;
  const int m = static_cast<int>(meas.size());
  const Eigen::MatrixXd& P = state_.P;
  const int n = static_cast<int>(P.rows());
  const double variance = pixel_sigma() * pixel_sigma();
  // Where each measured point's parameters start in the state.
  std::vector<int> point_columns(m);
  for (int k = 0; k < m; ++k) point_columns[k] = state_.point_column(meas[k].slot);
  // The iterated EKF: x_{i+1} = x_prior + K_i (z - h(x_i) + H_i (x_i - x_prior)), K_i and H_i
  // at x_i.
  // At the constant velocity: one linearisation, at the propagated pose moved by the last updated
  // frame's motion, a point the frame's own pixels did not choose.
  const bool at_constant_velocity = linearised_at == LinearisedAt::kConstantVelocity;
  const int linearisations =
      at_given_points() || at_constant_velocity ? 1 : std::max(1, settings_.update_iterations);
  bool warm_step = false;
  Iterate at = first_iterate(meas, point_columns, predicted, linearisations, &warm_step);
  Iterate next;
  next.allocate(m, state_.num_camera_params());
  if (at_constant_velocity) {
    // M is camera to camera, so it moves cam_from_state in whatever frame the state is:
    // R' = R_M R (a left perturbation log R_M), t' = R_M t + t_M.
    const Eigen::Isometry3d& motion = *walk_linearisation_motion_;
    next.offset = Eigen::VectorXd::Zero(n);
    next.offset.head<3>() = so3::log(motion.linear());
    next.offset.segment<3>(3) =
        motion.linear() * state_.mean.t + motion.translation() - state_.mean.t;
    // g and the cost serve only the damping between linearisations, and there is one.
    next.g = Eigen::VectorXd::Zero(n);
    next.cost = 0;
    const FilterMean constant_velocity_mean = state_.mean.plus(next.offset, kMinInverseDepth);
    project_iterate(meas, point_columns, constant_velocity_mean, true, false, 0, at, &next);
    std::swap(at, next);
  }
  c->residuals.resize(m);

  // P H^T and S's factor are built in the candidate: every step is taken (the warm start's is
  // overwritten by the next linearisation).
  Eigen::MatrixXd& PHt = c->PHt;
  Eigen::MatrixXd& S = c->S_factor;
  PHt.resize(n, 2 * m);
  S.resize(2 * m, 2 * m);
  Eigen::MatrixXd HPHt;
  const double settled_px =
      (predicted ? settings_.predicted_settle_sigmas : 0.03) * pixel_sigma();
  // Levenberg's damping in the prior's metric, mu |x - x_i|^2_P^-1 added to the posterior cost:
  // the step is the iterated EKF's with P / (1 + mu) and the offset x_i - x_prior shrunk by
  // 1 / (1 + mu). mu starts at 0 (the plain iterated EKF) and follows Marquardt's rule on the
  // ratio of the actual to the linear model's decrease of the posterior cost. Unlike
  // Levenberg-Marquardt, a step that raises the cost is still taken (and the next one damped):
  // early in a sequence, where the scale is barely known, the translation and the depths
  // oscillate along a curved valley, and refusing such steps crawls along it instead.
  double mu = 0;
  bool damped = false;  // whether the candidate came from a damped step
  c->linearisations = 0;
  for (int linearisation = 0;; ++linearisation) {
    ++c->linearisations;
    const double shrink = 1 / (1 + mu);
    // P H^T and S = H P H^T / (1 + mu) + R from the blocks of H; the Cholesky factorisation
    // reads S's lower triangle only.
    project_covariance(at, point_columns, &PHt, &S);
    if (const int k = state_.num_camera_params(); k > 0)
      c->unestimated = at.H_camera * PHt.middleRows(FilterState::kCameraColumn, k);
    if (mu > 0) {
      HPHt = S;  // for the undamped factor the covariance needs
      S *= shrink;
    }
    S.diagonal().array() += variance;
    if (!cholesky_lower_in_place(&S)) {
      // P is not positive definite: no update.
      c->mean = state_.mean;
      PHt.resize(0, 0);
      return;
    }
    const double model_cost = take_step(at, point_columns, PHt, S, mu, &next);
    const double prior_cost = next.g.dot(next.offset);
    FilterMean moved = state_.mean.plus(next.offset, kMinInverseDepth);
    next.offset.tail(n - state_.first_point_column()) = moved.points - state_.mean.points;

    // Project the new iterate (its pixels are the outlier test's residuals). Settled when its
    // predicted pixels moved by less than 3 % of the pixel noise, or a damped step by less than
    // that shrunk as the step was: linearising there again would change nothing measurable,
    // and P H^T and S stay this linearisation's, which the iterate came from.
    const bool may_relinearise = linearisation + 1 < linearisations;
    next.cost = prior_cost;
    const IterateCheck check = project_iterate(meas, point_columns, moved, may_relinearise,
                                               warm_step, settled_px * shrink, at, &next);
    const bool settled = check.settled, projected = check.projected;
    const double linearisation_error = check.linearisation_error;
    const double gain = (at.cost - next.cost) / std::max(at.cost - model_cost, 1e-12);
    std::swap(at, next);
    if (warm_step) {
      // Only a linearisation point (its H is not the measurements'): no candidate yet.
      warm_step = false;
      continue;
    }
    c->mean = std::move(moved);
    for (int k = 0; k < m; ++k) c->residuals[k] = at.residual.segment<2>(2 * k).norm();
    c->residual = at.residual;
    damped = mu > 0;
    if (!may_relinearise || settled) break;
    if (!damped && projected && linearisation_error < settled_px) break;
    if (gain > 0.75)
      mu = mu < 0.25 ? 0 : mu / 4;
    else if (!(gain >= 0.25))
      mu = mu == 0 ? 1 : 2 * mu;
  }
  // The covariance downdate uses the linearisation the candidate came from, undamped.
  if (damped) {
    S = HPHt;
    S.diagonal().array() += variance;
    if (!cholesky_lower_in_place(&S)) PHt.resize(0, 0);
  }
}

void OnlineFilter::project_covariance(const Iterate& at, const std::vector<int>& point_columns,
                                      Eigen::MatrixXd* PHt, Eigen::MatrixXd* S) const {
  const Eigen::MatrixXd& P = state_.P;
  const int camera_params = state_.num_camera_params();
  constexpr int kCamera = FilterState::kCameraColumn;
  multiply(P.leftCols<6>(), false, at.H_pose, true, *PHt);
  add_point_columns(P, point_columns, at.H_point, PHt);
  if (camera_params > 0)
    PHt->noalias() += P.middleCols(kCamera, camera_params) * at.H_camera.transpose();
  multiply(at.H_pose, false, PHt->topRows<6>(), false, *S);
  add_point_rows_lower(*PHt, point_columns, at.H_point, S);
  if (camera_params > 0) S->noalias() += at.H_camera * PHt->middleRows(kCamera, camera_params);
}

double OnlineFilter::take_step(const Iterate& at, const std::vector<int>& point_columns,
                               const Eigen::MatrixXd& PHt, const Eigen::MatrixXd& S_factor,
                               double mu, Iterate* next) const {
  const double shrink = 1 / (1 + mu);
  const int camera_params = state_.num_camera_params();
  constexpr int kCamera = FilterState::kCameraColumn;
  Eigen::VectorXd weighted = at.innovation - (1 - shrink) * at.H_offset;
  S_factor.triangularView<Eigen::Lower>().solveInPlace(weighted);
  S_factor.triangularView<Eigen::Lower>().adjoint().solveInPlace(weighted);
  next->offset.noalias() = PHt * weighted;
  next->g = mu * at.g;
  next->g.head<6>().noalias() += at.H_pose.transpose() * weighted;
  if (camera_params > 0)
    next->g.segment(kCamera, camera_params).noalias() += at.H_camera.transpose() * weighted;
  for (size_t k = 0; k < point_columns.size(); ++k)
    next->g.segment<FilterState::kPointSize>(point_columns[k]).noalias() +=
        at.H_point[k].transpose() * weighted.segment<2>(2 * static_cast<Eigen::Index>(k));
  next->offset = shrink * (next->offset + mu * at.offset);
  // Considered, never moved. Undamped this is Schmidt's step exactly; a damped one (under the
  // random walk only, about one frame in twelve on the rover) weighs the considered states' share
  // of the innovation covariance by 1 / (1 + mu), and its cost ratio is approximate.
  state_.hold_considered(&next->offset);
  next->g *= shrink;
  // The cost's prior part is |x - x_prior|^2_P^-1 = g^T P g with x - x_prior = P g; the linear
  // model's residual r - H d is variance times the weighted innovation.
  const double variance = pixel_sigma() * pixel_sigma();
  return variance * weighted.squaredNorm() + next->g.dot(next->offset);
}

OnlineFilter::IterateCheck OnlineFilter::project_iterate(
    const std::vector<Measurement>& meas, const std::vector<int>& point_columns,
    const FilterMean& moved, bool jacobians, bool warm_step, double settled_px, const Iterate& at,
    Iterate* next_iterate) const {
  Iterate& next = *next_iterate;
  const double variance = pixel_sigma() * pixel_sigma();
  const int m = static_cast<int>(meas.size());
  const Eigen::Matrix3d chart = so3::left_jacobian(next.offset.head<3>());
  IterateCheck check;
  for (int k = 0; k < m; ++k) {
    const int s = meas[k].slot;
    Linearisation lin;
    if (!linearise(state_.anchor(s), moved.R, moved.t, moved.params(s), jacobians, &lin)) {
      // Off the mirror here: its previous linearisation stays (the prior's, if that one was
      // the established points' only), and it fails the outlier test unless a later iterate
      // brings it back.
      const bool stale_prior = warm_step && at.H_point[k].isZero();
      next.H_pose.middleRows<2>(2 * k) =
          stale_prior ? meas[k].at_prior.pose : at.H_pose.middleRows<2>(2 * k);
      next.H_point[k] = stale_prior ? meas[k].at_prior.point : at.H_point[k];
      if (next.H_camera.cols() > 0)
        next.H_camera.middleRows<2>(2 * k) =
            stale_prior ? meas[k].at_prior.camera : at.H_camera.middleRows<2>(2 * k).eval();
      next.pixels.segment<2>(2 * k) = at.pixels.segment<2>(2 * k);
      next.residual.segment<2>(2 * k).setConstant(INFINITY);
      next.innovation.segment<2>(2 * k) =
          stale_prior ? (meas[k].pixel - meas[k].at_prior.pixel).eval()
                      : at.innovation.segment<2>(2 * k);
      next.H_offset.segment<2>(2 * k) =
          stale_prior ? Eigen::Vector2d::Zero().eval() : at.H_offset.segment<2>(2 * k).eval();
      check.projected = false;
      continue;
    }
    if ((lin.pixel - at.pixels.segment<2>(2 * k)).cwiseAbs().maxCoeff() >= settled_px)
      check.settled = false;
    const Eigen::Vector2d linear_pixel =
        at.pixels.segment<2>(2 * k) +
        at.H_pose.middleRows<2>(2 * k) * (next.offset.head<6>() - at.offset.head<6>()) +
        at.H_point[k] * (next.offset.segment<FilterState::kPointSize>(point_columns[k]) -
                         at.offset.segment<FilterState::kPointSize>(point_columns[k]));
    check.linearisation_error =
        std::max(check.linearisation_error, (lin.pixel - linear_pixel).cwiseAbs().maxCoeff());
    next.cost += next.take(k, lin, meas[k].pixel, point_columns[k], chart, jacobians) / variance;
  }
  if (!check.projected) next.cost = INFINITY;
  return check;
}

double OnlineFilter::Iterate::take(int k, const Linearisation& lin, const Eigen::Vector2d& observed,
                                   int point_column, const Eigen::Matrix3d& chart, bool jacobians) {
  pixels.segment<2>(2 * k) = lin.pixel;
  residual.segment<2>(2 * k) = observed - lin.pixel;
  if (jacobians) {
    H_pose.block<2, 3>(2 * k, 0) = lin.pose.leftCols<3>() * chart;
    H_pose.block<2, 3>(2 * k, 3) = lin.pose.rightCols<3>();
    H_point[k] = lin.point;
    if (H_camera.cols() > 0) H_camera.middleRows<2>(2 * k) = lin.camera;
    H_offset.segment<2>(2 * k) = H_pose.middleRows<2>(2 * k) * offset.head<6>() +
                                 lin.point * offset.segment<FilterState::kPointSize>(point_column);
    innovation.segment<2>(2 * k) = residual.segment<2>(2 * k) + H_offset.segment<2>(2 * k);
  }
  return residual.segment<2>(2 * k).squaredNorm();
}

void OnlineFilter::accept(Candidate* c) {
  state_.mean = std::move(c->mean);
  if (c->PHt.size() == 0) return;
  const Eigen::MatrixXd considered = state_.considered_covariance();
  downdate_covariance(&state_.P, &c->PHt, c->S_factor);
  state_.restore_considered_covariance(considered);
}

double OnlineFilter::motion_misfit(const std::map<int, Eigen::Vector2d>& seen,
                                   const std::vector<Measurement>& measurements) const {
  std::vector<double> scores;
  for (const auto& [track, pixel] : seen) {
    const int slot = state_.slot_of(track);
    // Those that do not project at the propagated state count as beyond any bound.
    if (slot >= 0 && state_.anchor(slot).updates >= kEstablishedUpdates)
      scores.push_back(std::numeric_limits<double>::infinity());
  }
  if (static_cast<int>(scores.size()) < kMinPointsToJudgeMotion)
    return std::numeric_limits<double>::quiet_NaN();
  size_t k = 0;
  for (const Measurement& m : measurements)
    if (state_.anchor(m.slot).updates >= kEstablishedUpdates) scores[k++] = prior_chi2(m);
  return core::percentile(scores, 0.5);
}

double OnlineFilter::misfit_after_update(const std::vector<Measurement>& measurements,
                                         double quantile) const {
  constexpr double kNotJudged = std::numeric_limits<double>::quiet_NaN();
  std::vector<int> established;
  for (size_t k = 0; k < measurements.size(); ++k)
    if (state_.anchor(measurements[k].slot).updates >= kEstablishedUpdates)
      established.push_back(static_cast<int>(k));
  if (static_cast<int>(established.size()) < kMinPointsToJudgeMotion) return kNotJudged;
  Candidate candidate;
  update(measurements, LinearisedAt::kIterates, &candidate);
  if (candidate.PHt.size() == 0) return kNotJudged;
  const std::vector<double> all =
      posterior_chi2(candidate.S_factor, candidate.residual, pixel_sigma() * pixel_sigma(),
                     candidate.unestimated.size() > 0 ? &candidate.unestimated : nullptr);
  std::vector<double> scores;
  for (int k : established) scores.push_back(all[k]);
  return core::percentile(scores, quantile);
}

bool OnlineFilter::fits_after_update(const std::vector<Measurement>& measurements) const {
  // NaN (not judged) compares false.
  return misfit_after_update(measurements, 0.5) <= settings_.outlier_chi2;
}

double OnlineFilter::prior_chi2(const Measurement& m) const {
  constexpr int kSize = FilterState::kPointSize;
  const int c = state_.point_column(m.slot);
  const Eigen::MatrixXd& P = state_.P;
  Eigen::Matrix<double, 2, 6 + kSize> H;
  H << m.at_prior.pose, m.at_prior.point;
  Eigen::Matrix<double, 6 + kSize, 6 + kSize> P_local;
  P_local << P.topLeftCorner<6, 6>(), P.block<6, kSize>(0, c), P.block<kSize, 6>(c, 0),
      P.block<kSize, kSize>(c, c);
  Eigen::Matrix2d S = H * P_local * H.transpose();
  if (const int k = state_.num_camera_params(); k > 0) {
    // The considered camera parameters' columns of H: their own block and their cross terms
    // with the pose's and the point's.
    constexpr int kCamera = FilterState::kCameraColumn;
    const Eigen::MatrixXd& H_camera = m.at_prior.camera;
    Eigen::Matrix<double, Eigen::Dynamic, 6 + kSize> P_camera_local(k, 6 + kSize);
    P_camera_local << P.block(kCamera, 0, k, 6), P.block(kCamera, c, k, kSize);
    const Eigen::Matrix2d cross = H_camera * P_camera_local * H.transpose();
    S += cross + cross.transpose() + H_camera * P.block(kCamera, kCamera, k, k) * H_camera.transpose();
  }
  S.diagonal().array() += pixel_sigma() * pixel_sigma();
  const Eigen::Vector2d y = m.pixel - m.at_prior.pixel;
  return y.dot(S.ldlt().solve(y));
}

bool OnlineFilter::process_frame(int frame, const std::vector<TrackPixel>& observations) {
  return process(frame, observations, nullptr);
}

std::map<int, Eigen::Vector2d> OnlineFilter::usable(const std::vector<TrackPixel>& observations) {
  std::map<int, Eigen::Vector2d> seen;
  for (const auto& o : observations)
    if (!excluded_.count(o.track)) seen[o.track] = o.pixel;
  // A rejected track no longer observed has ended: nothing needs to remember it.
  if (!smoothing_start_ && !excluded_.empty()) {
    std::set<int> still_excluded;
    for (const auto& o : observations)
      if (excluded_.count(o.track)) still_excluded.insert(o.track);
    excluded_.swap(still_excluded);
  }
  return seen;
}

std::vector<OnlineFilter::Measurement> OnlineFilter::measurements_of(
    const std::map<int, Eigen::Vector2d>& seen) const {
  std::vector<Measurement> measurements;
  for (const auto& [track, pixel] : seen) {
    const int slot = state_.slot_of(track);
    if (slot < 0) continue;
    Measurement measurement{slot, pixel, {}};
    const PointAnchor& anchor = state_.anchor(slot);
    if (!linearise(anchor, state_.mean.R, state_.mean.t, state_.mean.params(slot), true,
                   &measurement.at_prior))
      continue;
    if (at_given_points()) {
      const Eigen::Isometry3d T = linearisation_points_.cam_from_world(frame_);
      Linearisation given;
      // The given point about the origin as the state now has it.
      const PointParams at = state_.mean.params(slot);
      PointAnchor moved_anchor = anchor;
      moved_anchor.origin += at.tail<3>();
      PointParams given_params = moved_anchor.params_of(linearisation_points_.world_point(track));
      given_params.tail<3>() = at.tail<3>();
      if (linearise(anchor, T.linear(), T.translation(), given_params, true, &given)) {
        measurement.at_prior.pose = given.pose;
        measurement.at_prior.point = given.point;
        measurement.at_prior.camera = given.camera;
      }
    }
    measurements.push_back(measurement);
  }
  return measurements;
}

double OnlineFilter::residual_limit_px() const {
  // In pixel_sigmas under the chi-square rule: at the noise taken.
  return settings_.residual_limit_px() *
         (settings_.outlier_test == OutlierTest::kPixels ? 1.0 : noise_scale_);
}

void OnlineFilter::measure_noise(const std::vector<double>& established_scores) {
  // Kept at pixel_sigma's scale, whatever noise they were scored at: an established point's
  // score goes about as one over the noise's variance (exactly where the prediction's own
  // variance is small beside it; otherwise the first measure is pulled toward the stated noise,
  // and later ones settle on the true one).
  for (const double score : established_scores) {
    if (!std::isfinite(score)) continue;  // off the mirror: no measure of the noise
    const double at_stated = score * noise_scale_ * noise_scale_;
    if (recent_scores_.size() < kNoiseWindow) {
      recent_scores_.push_back(at_stated);
    } else {
      recent_scores_[recent_next_] = at_stated;
      recent_next_ = (recent_next_ + 1) % kNoiseWindow;
    }
  }
  if (recent_scores_.size() < kMinScoresForNoise) return;
  // A good measurement's score is chi-square(2) at the noise.
  take_noise(core::percentile(recent_scores_, 0.5) / kChiSquare2Median);
}

double OnlineFilter::noise_ratio() const {
  if (recent_scores_.size() < kMinScoresForNoise) return 1;
  return core::percentile(recent_scores_, 0.5) / kChiSquare2Median / (noise_scale_ * noise_scale_);
}

void OnlineFilter::take_noise(double implied_scale2) {
  // Taken beyond twice the stated variance, let go below 1.5 times (a median of 400 scores
  // wobbles by about 7 %, and without the gap the noise taken flipped near the threshold), and
  // at most kMaxNoiseScale times the stated noise: a filter that has lost its way sees every
  // track off, and taking that as noise would accept them all.
  const bool taken = noise_scale_ > 1;
  if (!(implied_scale2 > (taken ? kLetGoNoiseRatio : kTakeNoiseRatio)))
    noise_scale_ = 1;
  else
    noise_scale_ = std::min(std::sqrt(implied_scale2), kMaxNoiseScale);
}

bool OnlineFilter::update_rejecting_outliers(std::vector<Measurement> measurements,
                                             LinearisedAt linearised_at,
                                             std::set<int>* rejected_slots) {
  if (settings_.innovation_gate_chi2 > 0) {
    std::vector<Measurement> kept;
    for (const auto& m : measurements) {
      if (prior_chi2(m) > settings_.innovation_gate_chi2)
        rejected_slots->insert(m.slot);
      else
        kept.push_back(m);
    }
    measurements.swap(kept);
  }
  Candidate candidate;
  bool first_pass = true;  // the frame's scores before any is rejected measure the noise
  while (!measurements.empty()) {
    update(measurements, linearised_at, &candidate);
    linearisations_ += candidate.linearisations;
    // Without a factor of S (P not positive definite) only the pixels can be judged.
    const bool chi2 = settings_.outlier_test == OutlierTest::kChiSquare && candidate.PHt.size() > 0;
    std::vector<double> scores = candidate.residuals;
    if (chi2) {
      // A point in its first updates has a depth the linearisation does not hold: its update
      // leaves a residual along the parallax that the linear model says it would absorb (a good
      // track's second sighting, 1.6 px off, scored 1,700). Judged by its innovation instead, as
      // the prediction, with its wide depth, had it.
      scores = posterior_chi2(candidate.S_factor, candidate.residual,
                              pixel_sigma() * pixel_sigma(),
                              candidate.unestimated.size() > 0 ? &candidate.unestimated : nullptr);
      std::vector<double> established;
      for (size_t k = 0; k < measurements.size(); ++k) {
        if (state_.anchor(measurements[k].slot).updates < kEstablishedUpdates)
          scores[k] = prior_chi2(measurements[k]);
        else if (first_pass && settings_.measure_noise)
          established.push_back(scores[k]);
      }
      if (first_pass && settings_.measure_noise) {  // under the chi-square test only
        const double taken = noise_scale_;
        measure_noise(established);
        // Judged again at the noise now taken, before any is rejected.
        if (std::abs(noise_scale_ / taken - 1) > 0.1) {
          first_pass = false;
          continue;
        }
      }
    }
    first_pass = false;
    const double limit = chi2 ? settings_.outlier_chi2 : residual_limit_px();
    const auto worst = std::max_element(scores.begin(), scores.end());
    if (!(*worst <= limit)) {
      // Drop the worst track, redo the update from the prediction.
      const auto index = worst - scores.begin();
      rejected_slots->insert(measurements[index].slot);
      measurements.erase(measurements.begin() + index);
      continue;
    }
    accept(&candidate);
    for (const auto& m : measurements) ++state_.anchor(m.slot).updates;
    return true;
  }
  return false;
}

bool OnlineFilter::process(int frame, const std::vector<TrackPixel>& observations,
                           const MotionPrediction* motion) {
  previous_frame_ = frame_;
  frame_ = frame;
  const std::map<int, Eigen::Vector2d> seen = usable(observations);

  if (!started_) {
    started_ = true;
    for (const auto& [track, pixel] : seen) {
      if (state_.num_slots() >= settings_.max_live_points) {
        ++not_admitted_;
        continue;
      }
      add_point(track, pixel);
    }
    record_start_frame(frame, observations, nullptr, state_.mean.sensors);
    last_pose_ = state_.world_cam_from_world();
    return true;
  }

  // Tracks not seen in this frame have ended: their points leave the state.
  for (int s = state_.num_slots() - 1; s >= 0; --s)
    if (!seen.count(state_.track_of(s))) end_point(s);

  const OriginFollowsCamera follows = settings_.origin_follows_camera;
  if ((follows == OriginFollowsCamera::kAlways ||
       (follows == OriginFollowsCamera::kVisionAlone && !motion)) &&
      !smoothing_start_ && !at_given_points() && camera_far_from_origin()) {
    // The window lives in one state frame: it closes before the frame moves, and opens after.
    const bool window = window_open_ && !motion && window_on();
    if (window) close_window();
    state_.move_origin_to_camera(!turns_with_camera(
        settings_, motion && measures_whole_motion(*motion, settings_.rotation_walk_sigma)));
    if (window) open_window();
  }
  const SensorStates predicted_at = state_.mean.sensors;
  const MotionPrediction* given = motion;
  std::vector<Measurement> measurements;
  const bool propagated_by_walk = !motion;
  if (motion) {
    measurements = propagate_checked(seen, &motion);
  } else {
    propagate();
    measurements = measurements_of(seen);
    refused_in_a_row_ = 0;  // no sensors' motion to refuse
  }
  // A refused motion's fallback, the constant velocity or the random walk, is as loose as the
  // random walk, and updated as under it.
  const bool sensors_predicted = motion != nullptr && motion == given;
  // FilterSettings::linearise_at_constant_velocity acts where the walk alone propagated, once a
  // frame's motion is known.
  LinearisedAt linearised_at = LinearisedAt::kIterates;
  if (sensors_predicted)
    linearised_at = LinearisedAt::kPrediction;
  else if (settings_.linearise_at_constant_velocity && propagated_by_walk && !at_given_points() &&
           walk_linearisation_motion_)
    linearised_at = LinearisedAt::kConstantVelocity;

  std::set<int> rejected_slots;
  // The window's pixels, while one is open: those measured (the rejected leave it) and the new
  // points' first.
  std::set<int> window_tracks;
  if (window_open_)
    for (const Measurement& m : measurements) window_tracks.insert(state_.track_of(m.slot));
  if (motion) predicted_ = true;
  const bool updated =
      update_rejecting_outliers(std::move(measurements), linearised_at, &rejected_slots);
  // Named by track: removing a slot moves another into its place.
  std::vector<int> rejected_tracks;
  for (int slot : rejected_slots) rejected_tracks.push_back(state_.track_of(slot));
  for (int track : rejected_tracks) reject(track, frame);

  for (const auto& [track, pixel] : seen)
    if (state_.slot_of(track) < 0 && !excluded_.count(track)) {
      if (state_.num_slots() >= settings_.max_live_points) {
        ++not_admitted_;
        continue;
      }
      add_point(track, pixel);
      if (window_open_) window_tracks.insert(track);
    }
  record_start_frame(frame, observations, motion, predicted_at);
  record_window_frame(seen, window_tracks);
  note_pose();
  if (updated) walk_linearisation_motion_ = last_motion_;
  // A frame the images did not update has the sensors' own motion: no judge of them.
  if (given && updated && !smoothing_start_ && !at_given_points()) judge_motion_parts(*given);
  return updated;
}

void OnlineFilter::note_pose() {
  const Eigen::Isometry3d pose = state_.world_cam_from_world();
  // The smoothed start may just have revised the previous frame.
  const auto smoothed = smoothed_start_.find(previous_frame_);
  const Eigen::Isometry3d& previous =
      smoothed != smoothed_start_.end() ? smoothed->second : last_pose_;
  last_motion_ = pose * previous.inverse();
  last_pose_ = pose;
}

void OnlineFilter::finish_start() {
  if (smoothing_start_ && start_frames_.size() >= 2) smooth_start();
}

void OnlineFilter::smooth_start() {
  solve_start();
  std::map<int, Eigen::Vector3d> held;
  held.swap(held_points_);
  for (const auto& [track, point] : held) hand_over(track, point);
}

void OnlineFilter::record_start_frame(int frame, const std::vector<TrackPixel>& observations,
                                      const MotionPrediction* motion,
                                      const SensorStates& predicted_at) {
  if (!smoothing_start_) return;
  StartFrame f;
  f.frame = frame;
  f.R = state_.mean.R;
  f.t = state_.mean.t;
  f.random_walk = motion == nullptr;
  if (motion) f.motion = *motion;  // the sensors' errors are the start's to solve
  f.predicted_at = predicted_at;
  for (const auto& o : observations)
    if (state_.slot_of(o.track) >= 0) f.observations.push_back(o);
  start_frames_.push_back(std::move(f));
  if (static_cast<int>(start_frames_.size()) >= settings_.smoothed_start_frames) smooth_start();
}

}  // namespace omnisfm::sfm
