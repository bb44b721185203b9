// The filter's sliding window (FilterSettings::smoothing_window_frames): the frames since the
// window opened solved again from the filter's estimate where it opened, and the filter restarted
// from the solution.
//
// The window keeps the filter's own model of a point: its angles and inverse depth about an
// anchor whose origin is the ray's start, which moves with the pose it was started from. A point
// the prior holds keeps its six parameters (the origin's offset one of them, as in the state); a
// point started in the window has three, its origin's offset a function of that pose. Solved
// about fixed origins instead, the window reintroduced what the anchors removed (the pose's
// translation error entering a point's angles divided by its guessed depth): over 1,000 frames of
// the drive with exact tracks the orientation's published sigma grew to 0.52 deg where the
// filter's own grows to 0.88.

#include <ceres/normal_prior.h>
#include <ceres/problem.h>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

#include "omnisfm/sfm/online_filter.h"
#include "start_window_costs.h"
#include "window_costs.h"

namespace omnisfm::sfm {
namespace {


// A window's solve grows with the cube of the points it holds (the prior ties them all to its
// first pose): about 30 ms at 30 points, 0.3 s at 110. Beyond this many live points it is not
// solved; on the simulated rover, with 110, the windows had changed no figure.
constexpr int kMaxWindowPoints = 60;

}  // namespace

// The window's solution as the filter's restart needs it: the last pose, and per live slot its
// parameters; their covariance (the pose's six, then six per slot) and its covariance with the
// state frame's place.
struct OnlineFilter::WindowSolution {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  std::vector<PointParams> params;
  Eigen::MatrixXd covariance, with_origin;
};

bool OnlineFilter::window_on() const {
  // The window models the random walk alone, and carries the covariance with the state frame's
  // place but not with the sensors' states or the considered camera parameters.
  return settings_.smoothing_window_frames > 0 && !smoothing_start_ && !at_given_points() &&
         !predicted_ && state_.num_camera_params() == 0;
}

void OnlineFilter::forget_window_track(int track) {
  for (WindowFrame& f : window_frames_)
    f.observations.erase(std::remove_if(f.observations.begin(), f.observations.end(),
                                        [track](const TrackPixel& o) { return o.track == track; }),
                         f.observations.end());
  window_starts_.erase(track);
  window_latest_.erase(track);
}

void OnlineFilter::retire_window_track(int track) {
  if (!window_latest_.count(track) && !window_prior_.place.count(track)) return;
  const int key = next_retired_key_--;
  for (WindowFrame& f : window_frames_)
    for (TrackPixel& o : f.observations)
      if (o.track == track) o.track = key;
  const auto rename = [&](auto& map) {
    if (auto entry = map.extract(track)) {
      entry.key() = key;
      map.insert(std::move(entry));
    }
  };
  rename(window_prior_.place);
  rename(window_starts_);
  rename(window_latest_);
}

void OnlineFilter::open_window() {
  window_open_ = true;
  window_frames_.clear();
  window_starts_.clear();
  window_latest_.clear();
  WindowPrior& prior = window_prior_;
  prior = WindowPrior{};
  prior.R = state_.mean.R;
  prior.t = state_.mean.t;
  std::vector<int> columns;
  for (int k = 0; k < 6; ++k) columns.push_back(k);
  for (int s = 0; s < state_.num_slots(); ++s) {
    prior.place[state_.track_of(s)] = s;
    prior.anchors.push_back(state_.anchor(s));
    prior.params.push_back(state_.mean.params(s));
    for (int k = 0; k < FilterState::kPointSize; ++k) columns.push_back(state_.point_column(s) + k);
  }
  const auto size = static_cast<Eigen::Index>(columns.size());
  prior.covariance.resize(size, size);
  prior.with_origin.resize(size, 6);
  for (Eigen::Index a = 0; a < size; ++a) {
    for (Eigen::Index b = 0; b < size; ++b)
      prior.covariance(a, b) = state_.P(columns[a], columns[b]);
    prior.with_origin.row(a) = state_.P.block<1, 6>(columns[a], FilterState::kOriginColumn);
  }
}

void OnlineFilter::record_window_frame(const std::map<int, Eigen::Vector2d>& seen,
                                       const std::set<int>& tracks) {
  if (!window_on()) {
    window_open_ = false;
    window_frames_.clear();
    return;
  }
  if (!window_open_) {
    open_window();
    return;
  }
  WindowFrame f{state_.mean.R, state_.mean.t, {}};
  for (int s = 0; s < state_.num_slots(); ++s) {
    const int track = state_.track_of(s);
    if (const auto pixel = seen.find(track); pixel != seen.end() && tracks.count(track))
      f.observations.push_back({track, pixel->second});
    window_latest_[track] = state_.mean.params(s);
  }
  window_frames_.push_back(std::move(f));
  if (static_cast<int>(window_frames_.size()) >= settings_.smoothing_window_frames) {
    close_window();
    open_window();
  }
}

void OnlineFilter::close_window() {
  if (!window_open_ || window_frames_.empty() || state_.num_slots() > kMaxWindowPoints) return;
  WindowSolution solution;
  const bool solved = solve_window(&solution);
  if (solved) restart_from_window(solution);
  ++(solved ? window_solves_ : window_refusals_);
}

bool OnlineFilter::solve_window(WindowSolution* solution) const {
  const WindowPrior& prior = window_prior_;
  const std::vector<WindowFrame>& frames = window_frames_;
  const int n = static_cast<int>(frames.size());

  // The unknowns: the poses 0..n (the prior's, then each frame's), then the points the window
  // observes, six parameters for the prior's, three for those started since.
  struct WindowPoint {
    int track = 0;
    int column = 0;
    int prior_place = -1;  // in the prior, else started in the window
    const WindowStart* start = nullptr;
    MovingOrigin origin{};
    Eigen::Matrix<double, 6, 1> x = Eigen::Matrix<double, 6, 1>::Zero();  // 3 used if started
    int size() const { return prior_place >= 0 ? 6 : 3; }
  };
  std::vector<WindowPoint> points;
  std::map<int, int> index;  // track -> its place in points
  int columns = 6 * (n + 1);
  for (const WindowFrame& f : frames)
    for (const TrackPixel& o : f.observations) {
      if (index.count(o.track)) continue;
      WindowPoint p;
      p.track = o.track;
      const auto latest = window_latest_.find(o.track);
      if (const auto k = prior.place.find(o.track); k != prior.place.end()) {
        p.prior_place = k->second;
        p.x = latest != window_latest_.end() ? latest->second : prior.params[k->second];
      } else if (const auto start = window_starts_.find(o.track); start != window_starts_.end()) {
        p.start = &start->second;
        const WindowFrame& from = frames[p.start->pose - 1];
        p.origin.placed = p.start->anchor.origin;
        p.origin.in_camera = from.R * p.origin.placed + from.t;
        p.x[2] = 1 / settings_.initial_depth;
        if (latest != window_latest_.end()) {
          // Its latest estimate about the origin where it was placed.
          const Eigen::Vector3d X = p.start->anchor.world_point(latest->second);
          if (p.start->anchor.basis.col(0).dot(X - p.origin.placed) > 0)
            p.x.head<3>() = p.start->anchor.params_of(X).head<3>();
        }
        p.x[2] = std::max(p.x[2], kMinInverseDepth);
      } else {
        continue;
      }
      p.column = columns;
      columns += p.size();
      index[o.track] = static_cast<int>(points.size());
      points.push_back(p);
    }
  // Every live point is observed in the last frame recorded; one that is not cannot restart.
  for (int s = 0; s < state_.num_slots(); ++s)
    if (!index.count(state_.track_of(s))) return false;

  // The prior over the first pose and the prior's points the window observes.
  std::vector<int> rows;      // of the prior's covariance
  std::vector<int> prior_of;  // per row, the unknowns' column it bears on
  for (int k = 0; k < 6; ++k) {
    rows.push_back(k);
    prior_of.push_back(k);
  }
  std::vector<int> prior_points;
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].prior_place < 0) continue;
    prior_points.push_back(static_cast<int>(i));
    for (int k = 0; k < 6; ++k) {
      rows.push_back(6 + 6 * points[i].prior_place + k);
      prior_of.push_back(points[i].column + k);
    }
  }
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd covariance(m, m), with_origin(m, 6);
  Eigen::VectorXd prior_mean(m);
  for (Eigen::Index a = 0; a < m; ++a) {
    for (Eigen::Index b = 0; b < m; ++b) covariance(a, b) = prior.covariance(rows[a], rows[b]);
    with_origin.row(a) = prior.with_origin.row(rows[a]);
  }
  prior_mean.head<3>().setZero();
  prior_mean.segment<3>(3) = prior.t;
  for (size_t k = 0; k < prior_points.size(); ++k)
    prior_mean.segment<6>(6 + 6 * static_cast<Eigen::Index>(k)) =
        prior.params[points[prior_points[k]].prior_place];
  covariance.diagonal().array() += kMinVariance;
  const Eigen::LLT<Eigen::MatrixXd> prior_llt(covariance);
  if (prior_llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd whitening = prior_llt.matrixL().solve(Eigen::MatrixXd::Identity(m, m));

  std::vector<Eigen::Matrix3d> R(n + 1);
  std::vector<PoseBlock> poses(n + 1, PoseBlock::Zero());
  R[0] = prior.R;
  poses[0].tail<3>() = prior.t;
  for (int i = 1; i <= n; ++i) {
    R[i] = frames[i - 1].R;
    poses[i].tail<3>() = frames[i - 1].t;
  }

  ceres::Problem problem;
  const double sigma = pixel_sigma();
  for (int i = 1; i <= n; ++i)
    for (const TrackPixel& o : frames[i - 1].observations) {
      const auto k = index.find(o.track);
      if (k == index.end()) continue;
      WindowPoint& p = points[k->second];
      const PointAnchor* anchor_of =
          p.prior_place >= 0 ? &prior.anchors[p.prior_place] : &p.start->anchor;
      PointPixel model = [this, anchor_of](const Eigen::Matrix3d& Rc, const Eigen::Vector3d& tc,
                                           const PointParams& params, bool jacobians,
                                           Eigen::Vector2d* pixel,
                                           Eigen::Matrix<double, 2, 6>* J_pose,
                                           Eigen::Matrix<double, 2, 6>* J_point) {
        Linearisation lin;
        if (!linearise(*anchor_of, Rc, tc, params, jacobians, &lin)) return false;
        *pixel = lin.pixel;
        if (jacobians) {
          *J_pose = lin.pose;
          *J_point = lin.point;
        }
        return true;
      };
      if (p.prior_place >= 0) {
        problem.AddResidualBlock(
            WindowPixelCost::of_prior_point(std::move(model), &R[i], o.pixel, sigma), nullptr,
            poses[i].data(), p.x.data());
      } else if (p.start->pose == i) {
        problem.AddResidualBlock(
            WindowPixelCost::of_started_point(std::move(model), &R[i], nullptr, p.origin, o.pixel,
                                              sigma),
            nullptr, poses[i].data(), p.x.data());
      } else {
        const int from = p.start->pose;
        problem.AddResidualBlock(WindowPixelCost::of_started_point(std::move(model), &R[i],
                                                                   &R[from], p.origin, o.pixel,
                                                                   sigma),
                                 nullptr, poses[i].data(), poses[from].data(), p.x.data());
      }
    }
  Eigen::Matrix<double, 6, 6> walk_weight = Eigen::Matrix<double, 6, 6>::Zero();
  walk_weight.diagonal().head<3>().setConstant(
      1 / std::max(std::pow(settings_.rotation_walk_sigma, 2), kMinVariance));
  walk_weight.diagonal().tail<3>().setConstant(
      1 / std::max(std::pow(settings_.translation_walk_sigma, 2), kMinVariance));
  Eigen::Vector4d no_sensors = Eigen::Vector4d::Zero();
  for (int i = 1; i <= n; ++i)
    problem.AddResidualBlock(
        new StartMotionCost({&R[i - 1], nullptr}, {&R[i], nullptr}, nullptr, walk_weight,
                            Eigen::Matrix<double, 6, 4>::Zero(), Eigen::Vector4d::Zero()),
        nullptr, poses[i - 1].data(), poses[i].data(), no_sensors.data());
  problem.SetParameterBlockConstant(no_sensors.data());
  std::vector<double*> prior_blocks{poses[0].data()};
  std::vector<int> prior_sizes{6};
  for (const int k : prior_points) {
    prior_blocks.push_back(points[k].x.data());
    prior_sizes.push_back(6);
  }
  const ceres::ResidualBlockId prior_block = problem.AddResidualBlock(
      new JointPriorCost(whitening, prior_mean, prior_sizes), nullptr, prior_blocks);
  // A started point's depth prior, as the filter starts it (about its ray's moving start).
  const Eigen::Matrix<double, 1, 3> depth_row(0, 0, 1 / settings_.inverse_depth_sigma);
  for (WindowPoint& p : points) {
    if (p.prior_place < 0)
      problem.AddResidualBlock(
          new ceres::NormalPrior(depth_row, Eigen::Vector3d(0, 0, 1 / settings_.initial_depth)),
          nullptr, p.x.data());
    problem.SetParameterLowerBound(p.x.data(), 2, kMinInverseDepth);
  }
  double cost = 0;
  if (!problem.Evaluate({}, &cost, nullptr, nullptr, nullptr)) return false;
  ceres::Solver::Summary summary;
  ceres::Solve(window_solver_options(), &problem, &summary);
  if (!summary.IsSolutionUsable()) return false;
  // The solution taken, and the problem re-centred on it, so that its Jacobians are the filter's
  // left perturbations there.
  for (int i = 0; i <= n; ++i) {
    R[i] = rotation_of(poses[i].data(), R[i]);
    poses[i].head<3>().setZero();
  }
  const auto params_of = [&](const WindowPoint& p) {
    if (p.prior_place >= 0) return PointParams(p.x);
    const int from = p.start->pose;
    PointParams params;
    params << p.x.head<3>(), p.origin.offset(R[from], poses[from].tail<3>());
    return params;
  };

  // Refused where a pixel the filter took is beyond the residual limit of the solution.
  const double limit = residual_limit_px();
  for (int i = 1; i <= n; ++i)
    for (const TrackPixel& o : frames[i - 1].observations) {
      const auto k = index.find(o.track);
      if (k == index.end()) continue;
      const WindowPoint& p = points[k->second];
      Linearisation lin;
      if (!linearise(p.prior_place >= 0 ? prior.anchors[p.prior_place] : p.start->anchor, R[i],
                     poses[i].tail<3>(), params_of(p), false, &lin) ||
          !((lin.pixel - o.pixel).norm() <= limit))
        return false;
    }

  // The normal equations at the solution. The restart's covariance is T A^-1 T^T, T taking the
  // unknowns to the last pose and the live points' six parameters (a started point's offset
  // through the pose it was started from); its covariance with the state frame's place goes
  // through the prior's mean, d(solution)/d(prior mean) = A^-1 W^T W on the prior's rows.
  // The prior's dense block is its information, added as it is (as a sparse product it took
  // most of the time).
  ceres::Problem::EvaluateOptions evaluate;
  for (int i = 0; i <= n; ++i) evaluate.parameter_blocks.push_back(poses[i].data());
  for (WindowPoint& p : points) evaluate.parameter_blocks.push_back(p.x.data());
  problem.GetResidualBlocks(&evaluate.residual_blocks);
  evaluate.residual_blocks.erase(std::remove(evaluate.residual_blocks.begin(),
                                             evaluate.residual_blocks.end(), prior_block),
                                 evaluate.residual_blocks.end());
  ceres::CRSMatrix crs;
  if (!problem.Evaluate(evaluate, nullptr, nullptr, nullptr, &crs)) return false;
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> J(
      crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()), crs.rows.data(),
      crs.cols.data(), crs.values.data());
  const Eigen::SparseMatrix<double> JtJ = J.transpose() * J;
  Eigen::MatrixXd A(JtJ);
  const Eigen::MatrixXd information = whitening.transpose() * whitening;
  for (Eigen::Index a = 0; a < m; ++a)
    for (Eigen::Index b = 0; b < m; ++b) A(prior_of[a], prior_of[b]) += information(a, b);
  const Eigen::LLT<Eigen::MatrixXd> llt(A);
  if (llt.info() != Eigen::Success) return false;
  const int live = state_.num_slots();
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(6 + FilterState::kPointSize * live, columns);
  T.block<6, 6>(0, 6 * n).setIdentity();
  solution->params.resize(live);
  for (int s = 0; s < live; ++s) {
    const WindowPoint& p = points[index.at(state_.track_of(s))];
    const int row = 6 + FilterState::kPointSize * s;
    if (p.prior_place >= 0) {
      T.block<6, 6>(row, p.column).setIdentity();
    } else {
      const int from = p.start->pose;
      T.block<3, 3>(row, p.column).setIdentity();
      T.block<3, 6>(row + 3, 6 * from) = p.origin.jacobian(R[from], poses[from].tail<3>());
    }
    solution->params[s] = params_of(p);
  }
  Eigen::MatrixXd through_prior = Eigen::MatrixXd::Zero(columns, 6);
  const Eigen::MatrixXd weighted = information * with_origin;
  for (Eigen::Index a = 0; a < m; ++a) through_prior.row(prior_of[a]) = weighted.row(a);
  // T A^-1 T^T = Y^T Y with Y = L^-1 T^T, A = L L^T.
  const Eigen::MatrixXd Y = llt.matrixL().solve(T.transpose());
  solution->covariance = Y.transpose() * Y;
  solution->with_origin = Y.transpose() * llt.matrixL().solve(through_prior);
  solution->R = R[n];
  solution->t = poses[n].tail<3>();
  return true;
}

void OnlineFilter::restart_from_window(const WindowSolution& solution) {
  std::vector<int> columns;
  for (int k = 0; k < 6; ++k) columns.push_back(k);
  for (int s = 0; s < state_.num_slots(); ++s)
    for (int k = 0; k < FilterState::kPointSize; ++k) columns.push_back(state_.point_column(s) + k);
  Eigen::MatrixXd& P = state_.P;
  for (size_t a = 0; a < columns.size(); ++a) {
    P.row(columns[a]).setZero();
    P.col(columns[a]).setZero();
  }
  for (size_t a = 0; a < columns.size(); ++a) {
    for (size_t b = 0; b < columns.size(); ++b) P(columns[a], columns[b]) = solution.covariance(a, b);
    P.block<1, 6>(columns[a], FilterState::kOriginColumn) = solution.with_origin.row(a);
    P.block<6, 1>(FilterState::kOriginColumn, columns[a]) = solution.with_origin.row(a).transpose();
  }
  state_.mean.R = solution.R;
  state_.mean.t = solution.t;
  for (int s = 0; s < state_.num_slots(); ++s)
    state_.mean.points.segment<FilterState::kPointSize>(FilterState::kPointSize * s) =
        solution.params[s];
}

}  // namespace omnisfm::sfm
