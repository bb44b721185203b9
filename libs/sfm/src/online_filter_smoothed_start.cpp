// The filter's smoothed start (online_filter.h): its own model over the first frames solved by
// Levenberg-Marquardt, and the filter restarted from the solution.

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "motion_prior_residual.h"
#include "omnisfm/sfm/online_filter.h"
#include "so3.h"

namespace omnisfm::sfm {
namespace {

constexpr int kMaxIterations = 50;
// A step that lowers chi-square by less than this moves the estimate by a small fraction of its
// standard deviation (as the batch's stopping rule).
constexpr double kChiSquareTolerance = 0.01;
// Variances below this (a walk sigma of 0: the pose cannot move) are held at it, so that the
// normal equations stay factorable.
constexpr double kMinVariance = 1e-12;

// The start solves each point about its anchor with the origin where it was placed: the window's
// poses carry the origin's uncertainty, and six parameters for three unknowns would leave the
// normal equations singular.
PointParams at_placed_origin(const Eigen::Vector3d& x) {
  PointParams params = PointParams::Zero();
  params.head<3>() = x;
  return params;
}

}  // namespace

void OnlineFilter::solve_start() {
  smoothing_start_ = false;
  std::vector<StartFrame> frames;
  frames.swap(start_frames_);
  std::map<int, PointAnchor> anchors;
  anchors.swap(start_anchors_);
  const int num_frames = static_cast<int>(frames.size());
  if (num_frames < 2) return;

  // Every point of the window at the filter's estimate.
  std::map<int, Eigen::Vector3d> params;
  for (const auto& f : frames)
    for (const auto& o : f.observations) {
      if (params.count(o.track) || !anchors.count(o.track)) continue;
      const int slot = state_.slot_of(o.track);
      const auto ended = held_points_.find(o.track);
      if (slot >= 0)
        params[o.track] = anchors[o.track].params_of(state_.world_point(slot)).head<3>();
      else if (ended != held_points_.end())
        params[o.track] = anchors[o.track].params_of(ended->second).head<3>();
    }
  std::vector<Eigen::Matrix3d> R(num_frames);
  std::vector<Eigen::Vector3d> t(num_frames);
  for (int i = 0; i < num_frames; ++i) {
    R[i] = frames[i].R;
    t[i] = frames[i].t;
  }
  std::vector<Eigen::Matrix<double, 6, 6>> motion_weight(num_frames);
  for (int i = 1; i < num_frames; ++i) {
    Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
    if (frames[i].random_walk) {
      covariance.diagonal().head<3>().setConstant(std::pow(settings_.rotation_walk_sigma, 2));
      covariance.diagonal().tail<3>().setConstant(std::pow(settings_.translation_walk_sigma, 2));
    } else {
      covariance = frames[i].motion.covariance;
    }
    covariance.diagonal() = covariance.diagonal().cwiseMax(kMinVariance);
    motion_weight[i] = covariance.inverse();
  }
  const double pixel_weight = 1 / (settings_.pixel_sigma * settings_.pixel_sigma);
  const double depth_weight = 1 / (settings_.inverse_depth_sigma * settings_.inverse_depth_sigma);
  const double prior_depth = 1 / settings_.initial_depth;
  // Vision alone fixes the scale only weakly (through the mirror's size), and the posterior's
  // scale moves as frames come: a scale the start changed would stretch the trajectory between
  // what it outputs and what the filter outputs after. So the filter's scale is kept - the
  // farthest camera of the window stays as far from the first - unless the vehicle's motion
  // sensors measured the motion, which fixes the scale on its own.
  bool motion_measured = false;
  for (int i = 1; i < num_frames; ++i) motion_measured = motion_measured || !frames[i].random_walk;
  int far = 1;
  for (int i = 1; i < num_frames; ++i)
    if (t[i].norm() > t[far].norm()) far = i;
  const double far_distance = motion_measured ? 0 : t[far].norm();
  const double scale_weight = 1 / std::pow(1e-4 * far_distance + 1e-12, 2);

  // The sensors' states (gyro bias, wheel scale) are unknowns too, one offset from the prior's
  // mean over the window (their walk within it neglected): each frame's motion was predicted at
  // the filter's estimate then, and moves by C_i (prior + offset - that estimate), C_i = [B S].
  // Held at their estimates, their errors would count as new in every frame and their
  // correlations with the poses would be lost (the rover's NEES over 25 seeds: 15.3, 52 % inside
  // the bound; with the bias folded into each frame's noise instead, 5.1 and 94 %).
  // The prior: the filter's first estimates, with the variances the predictions state (the
  // window begins at the first frame, before any sensor's state has moved).
  Eigen::Vector4d prior_variance = Eigen::Vector4d::Zero();
  for (int i = 1; i < num_frames; ++i) {
    prior_variance.head<3>() =
        prior_variance.head<3>().cwiseMax(frames[i].motion.bias_prior_variance);
    prior_variance[3] = std::max(prior_variance[3], frames[i].motion.wheel_scale_prior_variance);
  }
  Eigen::Vector4d sensor_prior_weight;
  for (int j = 0; j < 4; ++j)  // unused sensors: no motion depends on them, any weight will do
    sensor_prior_weight[j] = prior_variance[j] > 0 ? 1 / prior_variance[j] : 1;
  const SensorStates first;
  Eigen::Matrix<double, 4, 1> prior_sensors;
  prior_sensors << first.gyro_bias, first.wheel_scale;
  std::vector<Eigen::Matrix<double, 6, 4>> sensor_jacobian(num_frames);
  std::vector<Eigen::Matrix<double, 4, 1>> predicted_at(num_frames);
  for (int i = 1; i < num_frames; ++i) {
    sensor_jacobian[i] << frames[i].motion.bias_jacobian, frames[i].motion.wheel_scale_jacobian;
    predicted_at[i] << frames[i].predicted_at.gyro_bias, frames[i].predicted_at.wheel_scale;
  }

  // Unknowns: the poses of frames 1.. (the first fixes the gauge), the sensors' offset, the
  // points.
  std::map<int, int> index;
  const int pose_columns = 6 * (num_frames - 1);
  const int sensor_column = pose_columns;
  auto pose_column = [&](int i) { return 6 * (i - 1); };
  auto point_column = [&](int track) { return pose_columns + 4 + 3 * index.at(track); };

  // chi-square at (R, t, params), and with `A` the normal equations' matrix and gradient there.
  // Infinite where a point does not project.
  struct Worst {
    double pixels = 0;
    int track = -1, frame = 0;
  };
  auto evaluate = [&](const std::vector<Eigen::Matrix3d>& Rs, const std::vector<Eigen::Vector3d>& ts,
                      const Eigen::Vector4d& sensors, const std::map<int, Eigen::Vector3d>& x,
                      Eigen::MatrixXd* A, Eigen::VectorXd* g, Worst* worst) -> double {
    double cost = sensors.dot(sensor_prior_weight.cwiseProduct(sensors));
    if (A) {
      A->block<4, 4>(sensor_column, sensor_column).diagonal() += sensor_prior_weight;
      g->segment<4>(sensor_column) += sensor_prior_weight.cwiseProduct(sensors);
    }
    for (int i = 0; i < num_frames; ++i)
      for (const auto& o : frames[i].observations) {
        if (!index.count(o.track)) continue;
        Linearisation lin;
        if (!linearise(anchors.at(o.track), Rs[i], ts[i], at_placed_origin(x.at(o.track)),
                       A != nullptr, &lin))
          return INFINITY;
        const Eigen::Matrix<double, 2, 3> J_point = lin.point.leftCols<3>();
        const Eigen::Vector2d f = lin.pixel - o.pixel;
        cost += pixel_weight * f.squaredNorm();
        if (worst && f.norm() > worst->pixels) *worst = {f.norm(), o.track, frames[i].frame};
        if (!A) continue;
        const int c = point_column(o.track);
        A->block<3, 3>(c, c) += pixel_weight * J_point.transpose() * J_point;
        g->segment<3>(c) += pixel_weight * J_point.transpose() * f;
        if (i == 0) continue;
        const int p = pose_column(i);
        A->block<6, 6>(p, p) += pixel_weight * lin.pose.transpose() * lin.pose;
        A->block<6, 3>(p, c) += pixel_weight * lin.pose.transpose() * J_point;
        A->block<3, 6>(c, p) = A->block<6, 3>(p, c).transpose();
        g->segment<6>(p) += pixel_weight * lin.pose.transpose() * f;
      }
    for (int i = 1; i < num_frames; ++i) {
      MotionPriorResidual r = motion_prior_residual(
          Rs[i - 1], ts[i - 1], Rs[i], ts[i], frames[i].random_walk ? nullptr : &frames[i].motion);
      const Eigen::Matrix<double, 6, 4>& C = sensor_jacobian[i];
      r.e -= C * (prior_sensors + sensors - predicted_at[i]);
      const Eigen::Matrix<double, 6, 6>& W = motion_weight[i];
      cost += r.e.dot(W * r.e);
      if (!A) continue;
      const int p = pose_column(i);
      const int c = sensor_column;
      A->block<6, 6>(p, p) += r.J_current.transpose() * W * r.J_current;
      g->segment<6>(p) += r.J_current.transpose() * W * r.e;
      A->block<4, 4>(c, c) += C.transpose() * W * C;
      g->segment<4>(c) -= C.transpose() * W * r.e;
      A->block<4, 6>(c, p) -= C.transpose() * W * r.J_current;
      A->block<6, 4>(p, c) = A->block<4, 6>(c, p).transpose();
      if (i == 1) continue;
      const int q = pose_column(i - 1);
      A->block<6, 6>(q, q) += r.J_previous.transpose() * W * r.J_previous;
      A->block<6, 6>(q, p) += r.J_previous.transpose() * W * r.J_current;
      A->block<6, 6>(p, q) = A->block<6, 6>(q, p).transpose();
      g->segment<6>(q) += r.J_previous.transpose() * W * r.e;
      A->block<4, 6>(c, q) -= C.transpose() * W * r.J_previous;
      A->block<6, 4>(q, c) = A->block<4, 6>(c, q).transpose();
    }
    if (far_distance > 0) {
      const double f = ts[far].norm() - far_distance;
      cost += scale_weight * f * f;
      if (A) {
        const Eigen::Vector3d J = ts[far] / ts[far].norm();
        const int p = pose_column(far) + 3;
        A->block<3, 3>(p, p) += scale_weight * J * J.transpose();
        g->segment<3>(p) += scale_weight * J * f;
      }
    }
    for (const auto& [track, column] : index) {
      const double f = x.at(track).z() - prior_depth;
      cost += depth_weight * f * f;
      if (!A) continue;
      (*A)(point_column(track) + 2, point_column(track) + 2) += depth_weight;
      (*g)(point_column(track) + 2) += depth_weight * f;
    }
    return cost;
  };

  Eigen::MatrixXd A;
  Eigen::VectorXd g;
  Eigen::Vector4d sensors = Eigen::Vector4d::Zero();  // the offset from the prior
  auto normal_equations = [&]() {
    const int n = pose_columns + 4 + 3 * static_cast<int>(index.size());
    A = Eigen::MatrixXd::Zero(n, n);
    g = Eigen::VectorXd::Zero(n);
    return evaluate(R, t, sensors, params, &A, &g, nullptr);
  };

  // Levenberg-Marquardt, then the paper's rejection on the window: while the worst residual
  // exceeds the threshold, that track goes and the rest is solved again.
  for (;;) {
    index.clear();
    for (const auto& [track, x] : params)
      if (!excluded_.count(track)) index.emplace(track, static_cast<int>(index.size()));
    double cost = normal_equations();
    if (!std::isfinite(cost)) return;  // the filter's own estimate does not project: keep it
    double lambda = 1e-6;
    for (int iteration = 0; iteration < kMaxIterations && lambda < 1e8; ++iteration) {
      Eigen::MatrixXd damped = A;
      damped.diagonal() *= 1 + lambda;
      const Eigen::LLT<Eigen::MatrixXd> llt(damped);
      if (llt.info() != Eigen::Success) {
        lambda *= 10;
        continue;
      }
      const Eigen::VectorXd step = -llt.solve(g);
      std::vector<Eigen::Matrix3d> R_next = R;
      std::vector<Eigen::Vector3d> t_next = t;
      std::map<int, Eigen::Vector3d> params_next = params;
      const Eigen::Vector4d sensors_next = sensors + step.segment<4>(sensor_column);
      for (int i = 1; i < num_frames; ++i) {
        R_next[i] = so3::exp(step.segment<3>(pose_column(i))) * R[i];
        t_next[i] += step.segment<3>(pose_column(i) + 3);
      }
      for (const auto& [track, column] : index) {
        Eigen::Vector3d& x = params_next[track];
        x += step.segment<3>(point_column(track));
        x.z() = std::max(x.z(), kMinInverseDepth);
      }
      const double next_cost =
          evaluate(R_next, t_next, sensors_next, params_next, nullptr, nullptr, nullptr);
      if (!(next_cost < cost)) {
        lambda *= 10;
        continue;
      }
      R.swap(R_next);
      t.swap(t_next);
      params.swap(params_next);
      sensors = sensors_next;
      lambda = std::max(lambda / 10, 1e-9);
      const double decrease = cost - next_cost;
      cost = normal_equations();
      if (decrease < kChiSquareTolerance) break;
    }
    Worst worst;
    evaluate(R, t, sensors, params, nullptr, nullptr, &worst);
    if (!(worst.pixels > settings_.residual_limit_px())) break;
    reject(worst.track, worst.frame);
  }

  // The covariance of the last pose, the sensors and the live points: those columns of A's
  // inverse, in the order of the filter's state.
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) return;
  const int live = state_.num_slots();
  // columns[k]: the solve's column that the state's column state_columns[k] takes. The points'
  // origins stay where they were placed (zero rows and columns): the solve's points are about them.
  std::vector<int> columns, state_columns;
  for (int k = 0; k < 6; ++k) columns.push_back(pose_column(num_frames - 1) + k);
  for (int k = 0; k < 4; ++k) columns.push_back(sensor_column + k);
  for (int k = 0; k < 10; ++k) state_columns.push_back(k);
  for (int s = 0; s < live; ++s)
    for (int k = 0; k < 3; ++k) {
      columns.push_back(point_column(state_.track_of(s)) + k);
      state_columns.push_back(FilterState::point_column(s) + k);
    }
  Eigen::MatrixXd selection = Eigen::MatrixXd::Zero(A.rows(), columns.size());
  for (size_t k = 0; k < columns.size(); ++k) selection(columns[k], k) = 1;
  const Eigen::MatrixXd inverse_columns = llt.solve(selection);
  Eigen::MatrixXd& P = state_.P;
  const int size = FilterState::point_column(live);
  P.setZero(size, size);
  for (size_t a = 0; a < columns.size(); ++a)
    for (size_t b = 0; b < columns.size(); ++b)
      P(state_columns[a], state_columns[b]) =
          inverse_columns(columns[a], static_cast<Eigen::Index>(b));
  double bias_walk = 0;  // what the solve neglected, the bias's walk over the window
  for (int i = 1; i < num_frames; ++i) bias_walk += frames[i].motion.bias_walk_variance;
  for (int j = 0; j < 4; ++j) {
    const int c = FilterState::kBiasColumn + j;
    if (prior_variance[j] > 0) {
      if (j < 3) P(c, c) += bias_walk;
    } else {
      P.row(c).setZero();  // an unused sensor stays out of every product
      P.col(c).setZero();
    }
  }
  state_.mean.sensors.gyro_bias = prior_sensors.head<3>() + sensors.head<3>();
  state_.mean.sensors.wheel_scale = prior_sensors[3] + sensors[3];
  state_.mean.R = R.back();
  state_.mean.t = t.back();
  for (int s = 0; s < live; ++s)
    state_.mean.points.segment<FilterState::kPointSize>(FilterState::kPointSize * s) =
        at_placed_origin(params.at(state_.track_of(s)));
  for (const auto& [track, column] : index)
    if (held_points_.count(track))
      held_points_[track] = anchors.at(track).world_point(at_placed_origin(params.at(track)));
  for (int i = 0; i < num_frames; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R[i];
    T.translation() = t[i];
    smoothed_start_[frames[i].frame] = T;
  }
}

}  // namespace omnisfm::sfm
