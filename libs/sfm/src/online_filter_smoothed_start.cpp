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

// An estimate of the window: its frames' poses, the sensors' offset from their prior, its points
// (angles and inverse depth about their anchors).
struct OnlineFilter::StartEstimate {
  std::vector<Eigen::Matrix3d> R;
  std::vector<Eigen::Vector3d> t;
  Eigen::Vector4d sensors = Eigen::Vector4d::Zero();
  std::map<int, Eigen::Vector3d> points;
};

// The window's problem: the measurements, the depth priors and the motion priors of its frames,
// the sensors' prior and, vision alone, the scale held. Unknowns: the poses of frames 1.. (the
// first fixes the gauge), the sensors' offset, the points in `index`.
struct OnlineFilter::StartWindow {
  std::vector<StartFrame> frames;
  std::map<int, PointAnchor> anchors;
  std::vector<Eigen::Matrix<double, 6, 6>> motion_weight;  // per frame from the second
  double pixel_weight = 0, depth_weight = 0, prior_depth = 0;
  int far = 1;                // the camera farthest from the first
  double far_distance = 0;    // held there, vision alone; 0 with the motion measured
  double scale_weight = 0;
  Eigen::Vector4d prior_variance = Eigen::Vector4d::Zero();  // the sensors', 0 where unused
  Eigen::Vector4d sensor_prior_weight;
  Eigen::Vector4d prior_sensors;
  std::vector<Eigen::Matrix<double, 6, 4>> sensor_jacobian;
  std::vector<Eigen::Vector4d> predicted_at;
  std::map<int, int> index;  // track -> its point's place among the unknowns
  int pose_columns = 0;

  int num_frames() const { return static_cast<int>(frames.size()); }
  int sensor_column() const { return pose_columns; }
  int pose_column(int i) const { return 6 * (i - 1); }
  int point_column(int track) const { return pose_columns + 4 + 3 * index.at(track); }
  int size() const { return pose_columns + 4 + 3 * static_cast<int>(index.size()); }

  struct Worst {
    double pixels = 0;
    int track = -1, frame = 0;
  };
  // chi-square at x, and with `A` the normal equations' matrix and gradient there. Infinite where
  // a point does not project.
  double evaluate(const OnlineFilter& filter, const StartEstimate& x, Eigen::MatrixXd* A,
                  Eigen::VectorXd* g, Worst* worst) const;
  // J_x^T W J_c at x over the measurements, J_c their Jacobians in the considered camera
  // parameters (size() x FilterState::num_camera_params()).
  Eigen::MatrixXd camera_coupling(const OnlineFilter& filter, const StartEstimate& x) const;
  // x moved by a step in the unknowns' columns.
  StartEstimate moved(const StartEstimate& x, const Eigen::VectorXd& step) const;
};

OnlineFilter::StartWindow OnlineFilter::start_window(StartEstimate* x) {
  StartWindow w;
  w.frames.swap(start_frames_);
  w.anchors.swap(start_anchors_);
  const int num_frames = w.num_frames();
  if (num_frames < 2) return w;
  const std::vector<StartFrame>& frames = w.frames;

  // Every point of the window at the filter's estimate.
  for (const auto& f : frames)
    for (const auto& o : f.observations) {
      if (x->points.count(o.track) || !w.anchors.count(o.track)) continue;
      const int slot = state_.slot_of(o.track);
      const auto ended = held_points_.find(o.track);
      if (slot >= 0)
        x->points[o.track] = w.anchors[o.track].params_of(state_.world_point(slot)).head<3>();
      else if (ended != held_points_.end())
        x->points[o.track] = w.anchors[o.track].params_of(ended->second).head<3>();
    }
  x->R.resize(num_frames);
  x->t.resize(num_frames);
  for (int i = 0; i < num_frames; ++i) {
    x->R[i] = frames[i].R;
    x->t[i] = frames[i].t;
  }
  w.motion_weight.resize(num_frames);
  for (int i = 1; i < num_frames; ++i) {
    Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
    if (frames[i].random_walk) {
      covariance.diagonal().head<3>().setConstant(std::pow(settings_.rotation_walk_sigma, 2));
      covariance.diagonal().tail<3>().setConstant(std::pow(settings_.translation_walk_sigma, 2));
    } else {
      covariance = frames[i].motion.covariance;
    }
    covariance.diagonal() = covariance.diagonal().cwiseMax(kMinVariance);
    w.motion_weight[i] = covariance.inverse();
  }
  w.pixel_weight = 1 / (settings_.pixel_sigma * settings_.pixel_sigma);
  w.depth_weight = 1 / (settings_.inverse_depth_sigma * settings_.inverse_depth_sigma);
  w.prior_depth = 1 / settings_.initial_depth;
  // Vision alone fixes the scale only weakly (through the mirror's size), and the posterior's
  // scale moves as frames come: a scale the start changed would stretch the trajectory between
  // what it outputs and what the filter outputs after. So the filter's scale is kept - the
  // farthest camera of the window stays as far from the first - unless the vehicle's motion
  // sensors measured the motion, which fixes the scale on its own.
  bool motion_measured = false;
  for (int i = 1; i < num_frames; ++i) motion_measured = motion_measured || !frames[i].random_walk;
  for (int i = 1; i < num_frames; ++i)
    if (x->t[i].norm() > x->t[w.far].norm()) w.far = i;
  w.far_distance = motion_measured ? 0 : x->t[w.far].norm();
  w.scale_weight = 1 / std::pow(1e-4 * w.far_distance + 1e-12, 2);

  // The sensors' states (gyro bias, wheel scale) are unknowns too, one offset from the prior's
  // mean over the window (their walk within it neglected): each frame's motion was predicted at
  // the filter's estimate then, and moves by C_i (prior + offset - that estimate), C_i = [B S].
  // Held at their estimates, their errors would count as new in every frame and their
  // correlations with the poses would be lost (the rover's NEES over 25 seeds: 15.3, 52 % inside
  // the bound; with the bias folded into each frame's noise instead, 5.1 and 94 %).
  // The prior: the filter's first estimates, with the variances the predictions state (the
  // window begins at the first frame, before any sensor's state has moved).
  for (int i = 1; i < num_frames; ++i) {
    w.prior_variance.head<3>() =
        w.prior_variance.head<3>().cwiseMax(frames[i].motion.bias_prior_variance);
    w.prior_variance[3] = std::max(w.prior_variance[3], frames[i].motion.wheel_scale_prior_variance);
  }
  for (int j = 0; j < 4; ++j)  // unused sensors: no motion depends on them, any weight will do
    w.sensor_prior_weight[j] = w.prior_variance[j] > 0 ? 1 / w.prior_variance[j] : 1;
  const SensorStates first;
  w.prior_sensors << first.gyro_bias, first.wheel_scale;
  w.sensor_jacobian.resize(num_frames);
  w.predicted_at.resize(num_frames);
  for (int i = 1; i < num_frames; ++i) {
    w.sensor_jacobian[i] << frames[i].motion.bias_jacobian, frames[i].motion.wheel_scale_jacobian;
    w.predicted_at[i] << frames[i].predicted_at.gyro_bias, frames[i].predicted_at.wheel_scale;
  }
  w.pose_columns = 6 * (num_frames - 1);
  return w;
}

double OnlineFilter::StartWindow::evaluate(const OnlineFilter& filter, const StartEstimate& x,
                                           Eigen::MatrixXd* A, Eigen::VectorXd* g,
                                           Worst* worst) const {
  const std::vector<Eigen::Matrix3d>& Rs = x.R;
  const std::vector<Eigen::Vector3d>& ts = x.t;
  const Eigen::Vector4d& sensors = x.sensors;
  const int sensor_column = this->sensor_column();
  double cost = sensors.dot(sensor_prior_weight.cwiseProduct(sensors));
  if (A) {
    A->block<4, 4>(sensor_column, sensor_column).diagonal() += sensor_prior_weight;
    g->segment<4>(sensor_column) += sensor_prior_weight.cwiseProduct(sensors);
  }
  for (int i = 0; i < num_frames(); ++i)
    for (const auto& o : frames[i].observations) {
      if (!index.count(o.track)) continue;
      Linearisation lin;
      if (!filter.linearise(anchors.at(o.track), Rs[i], ts[i], at_placed_origin(x.points.at(o.track)),
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
  for (int i = 1; i < num_frames(); ++i) {
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
    const double f = x.points.at(track).z() - prior_depth;
    cost += depth_weight * f * f;
    if (!A) continue;
    (*A)(point_column(track) + 2, point_column(track) + 2) += depth_weight;
    (*g)(point_column(track) + 2) += depth_weight * f;
  }
  return cost;
}

Eigen::MatrixXd OnlineFilter::StartWindow::camera_coupling(const OnlineFilter& filter,
                                                          const StartEstimate& x) const {
  Eigen::MatrixXd coupling = Eigen::MatrixXd::Zero(size(), filter.state_.num_camera_params());
  for (int i = 0; i < num_frames(); ++i)
    for (const auto& o : frames[i].observations) {
      if (!index.count(o.track)) continue;
      Linearisation lin;
      if (!filter.linearise(anchors.at(o.track), x.R[i], x.t[i],
                            at_placed_origin(x.points.at(o.track)), true, &lin))
        continue;
      coupling.middleRows<3>(point_column(o.track)) +=
          pixel_weight * lin.point.leftCols<3>().transpose() * lin.camera;
      if (i > 0)
        coupling.middleRows<6>(pose_column(i)) += pixel_weight * lin.pose.transpose() * lin.camera;
    }
  return coupling;
}

OnlineFilter::StartEstimate OnlineFilter::StartWindow::moved(const StartEstimate& x,
                                                             const Eigen::VectorXd& step) const {
  StartEstimate next = x;
  next.sensors = x.sensors + step.segment<4>(sensor_column());
  for (int i = 1; i < num_frames(); ++i) {
    next.R[i] = so3::exp(step.segment<3>(pose_column(i))) * x.R[i];
    next.t[i] += step.segment<3>(pose_column(i) + 3);
  }
  for (const auto& [track, column] : index) {
    Eigen::Vector3d& p = next.points[track];
    p += step.segment<3>(point_column(track));
    p.z() = std::max(p.z(), kMinInverseDepth);
  }
  return next;
}

bool OnlineFilter::solve_start_window(StartWindow* w, StartEstimate* x, Eigen::MatrixXd* A) {
  Eigen::VectorXd g;
  auto normal_equations = [&]() {
    const int n = w->size();
    *A = Eigen::MatrixXd::Zero(n, n);
    g = Eigen::VectorXd::Zero(n);
    return w->evaluate(*this, *x, A, &g, nullptr);
  };
  // Levenberg-Marquardt, then the paper's rejection on the window: while the worst residual
  // exceeds the threshold, that track goes and the rest is solved again.
  for (;;) {
    w->index.clear();
    for (const auto& [track, p] : x->points)
      if (!excluded_.count(track)) w->index.emplace(track, static_cast<int>(w->index.size()));
    double cost = normal_equations();
    if (!std::isfinite(cost)) return false;  // the filter's own estimate does not project
    double lambda = 1e-6;
    for (int iteration = 0; iteration < kMaxIterations && lambda < 1e8; ++iteration) {
      Eigen::MatrixXd damped = *A;
      damped.diagonal() *= 1 + lambda;
      const Eigen::LLT<Eigen::MatrixXd> llt(damped);
      if (llt.info() != Eigen::Success) {
        lambda *= 10;
        continue;
      }
      const Eigen::VectorXd step = -llt.solve(g);
      StartEstimate next = w->moved(*x, step);
      const double next_cost = w->evaluate(*this, next, nullptr, nullptr, nullptr);
      if (!(next_cost < cost)) {
        lambda *= 10;
        continue;
      }
      std::swap(*x, next);
      lambda = std::max(lambda / 10, 1e-9);
      const double decrease = cost - next_cost;
      cost = normal_equations();
      if (decrease < kChiSquareTolerance) break;
    }
    StartWindow::Worst worst;
    w->evaluate(*this, *x, nullptr, nullptr, &worst);
    if (!(worst.pixels > settings_.residual_limit_px())) return true;
    reject(worst.track, worst.frame);
  }
}

void OnlineFilter::restart_from(const StartWindow& w, const StartEstimate& x,
                                const Eigen::MatrixXd& A) {
  // The covariance of the last pose, the sensors and the live points: those columns of A's
  // inverse, in the order of the filter's state.
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) return;
  const int num_frames = w.num_frames();
  const int live = state_.num_slots();
  // columns[k]: the solve's column that the state's column state_columns[k] takes. The points'
  // origins stay where they were placed (zero rows and columns): the solve's points are about them.
  std::vector<int> columns, state_columns;
  for (int k = 0; k < 6; ++k) columns.push_back(w.pose_column(num_frames - 1) + k);
  for (int k = 0; k < 4; ++k) columns.push_back(w.sensor_column() + k);
  for (int k = 0; k < 10; ++k) state_columns.push_back(k);
  for (int s = 0; s < live; ++s)
    for (int k = 0; k < 3; ++k) {
      columns.push_back(w.point_column(state_.track_of(s)) + k);
      state_columns.push_back(state_.point_column(s) + k);
    }
  Eigen::MatrixXd selection = Eigen::MatrixXd::Zero(A.rows(), columns.size());
  for (size_t k = 0; k < columns.size(); ++k) selection(columns[k], k) = 1;
  const Eigen::MatrixXd inverse_columns = llt.solve(selection);
  Eigen::MatrixXd& P = state_.P;
  const int size = state_.point_column(live);
  P.setZero(size, size);
  for (size_t a = 0; a < columns.size(); ++a)
    for (size_t b = 0; b < columns.size(); ++b)
      P(state_columns[a], state_columns[b]) =
          inverse_columns(columns[a], static_cast<Eigen::Index>(b));
  if (const int c = state_.num_camera_params(); c > 0) {
    // The window was solved with the camera as given, so its estimate errs with the camera's
    // error by the sensitivity -A^-1 A_xc: a covariance that adds, and the cross-covariance
    // with the considered parameters (filter_state.h).
    const Eigen::MatrixXd sensitivity = -llt.solve(w.camera_coupling(*this, x));
    Eigen::MatrixXd selected(columns.size(), c);
    for (size_t a = 0; a < columns.size(); ++a) selected.row(a) = sensitivity.row(columns[a]);
    const Eigen::MatrixXd cross = selected * settings_.camera_uncertainty.covariance;
    const Eigen::MatrixXd added = cross * selected.transpose();
    for (size_t a = 0; a < columns.size(); ++a) {
      for (size_t b = 0; b < columns.size(); ++b)
        P(state_columns[a], state_columns[b]) += added(a, b);
      P.block(state_columns[a], FilterState::kCameraColumn, 1, c) = cross.row(a);
      P.block(FilterState::kCameraColumn, state_columns[a], c, 1) = cross.row(a).transpose();
    }
  }
  state_.reset_camera_covariance();
  double bias_walk = 0;  // what the solve neglected, the bias's walk over the window
  for (int i = 1; i < num_frames; ++i) bias_walk += w.frames[i].motion.bias_walk_variance;
  for (int j = 0; j < 4; ++j) {
    const int c = FilterState::kBiasColumn + j;
    if (w.prior_variance[j] > 0) {
      if (j < 3) P(c, c) += bias_walk;
    } else {
      P.row(c).setZero();  // an unused sensor stays out of every product
      P.col(c).setZero();
    }
  }
  state_.mean.sensors.gyro_bias = w.prior_sensors.head<3>() + x.sensors.head<3>();
  state_.mean.sensors.wheel_scale = w.prior_sensors[3] + x.sensors[3];
  state_.mean.R = x.R.back();
  state_.mean.t = x.t.back();
  for (int s = 0; s < live; ++s)
    state_.mean.points.segment<FilterState::kPointSize>(FilterState::kPointSize * s) =
        at_placed_origin(x.points.at(state_.track_of(s)));
  for (const auto& [track, column] : w.index)
    if (held_points_.count(track))
      held_points_[track] = w.anchors.at(track).world_point(at_placed_origin(x.points.at(track)));
  for (int i = 0; i < num_frames; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = x.R[i];
    T.translation() = x.t[i];
    smoothed_start_[w.frames[i].frame] = T;
  }
}

void OnlineFilter::solve_start() {
  smoothing_start_ = false;
  StartEstimate x;
  StartWindow window = start_window(&x);
  if (window.num_frames() < 2) return;
  Eigen::MatrixXd A;
  // The filter's own estimate not projecting there, it is kept.
  if (!solve_start_window(&window, &x, &A)) return;
  restart_from(window, x, A);
}

}  // namespace omnisfm::sfm
