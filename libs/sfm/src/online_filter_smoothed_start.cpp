// The filter's smoothed start (online_filter.h): its own model over the first frames solved by
// Levenberg-Marquardt (Ceres), and the filter restarted from the solution.

#include <ceres/normal_prior.h>
#include <ceres/problem.h>

#include <Eigen/Cholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

#include "omnisfm/core/percentile.h"
#include "omnisfm/sfm/online_filter.h"
#include "start_window_costs.h"

namespace omnisfm::sfm {
namespace {

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
    double median_squared_pixels = 0;  // over the window's residuals
  };
  // The window's terms at x into `problem`: the poses of frames 1.. as `poses` (zero rotation
  // about x's, x's translations), the sensors' offset and the points as x's own storage.
  void add_terms(const OnlineFilter& filter, StartEstimate* x, std::vector<PoseBlock>* poses,
                 ceres::Problem* problem) const;
  // The unknowns' blocks in the order of the columns below.
  std::vector<double*> blocks(StartEstimate* x, std::vector<PoseBlock>* poses) const;
  // The normal equations' matrix J^T J of `problem` (add_terms') at x, its poses at zero rotation.
  Eigen::MatrixXd normal_equations(ceres::Problem* problem, StartEstimate* x,
                                   std::vector<PoseBlock>* poses) const;
  // The measurement farthest from its prediction at x.
  // With `with_median`, also the residuals' median (Worst::median_squared_pixels).
  Worst worst_pixel(const OnlineFilter& filter, const StartEstimate& x, bool with_median) const;
  // J_x^T W J_c at x over the measurements, J_c their Jacobians in the considered camera
  // parameters (size() x FilterState::num_camera_params()).
  Eigen::MatrixXd camera_coupling(const OnlineFilter& filter, const StartEstimate& x) const;
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
  w.pixel_weight = 1 / (pixel_sigma() * pixel_sigma());
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

void OnlineFilter::StartWindow::add_terms(const OnlineFilter& filter, StartEstimate* x,
                                          std::vector<PoseBlock>* poses,
                                          ceres::Problem* problem) const {
  poses->assign(num_frames(), PoseBlock::Zero());
  for (int i = 1; i < num_frames(); ++i) (*poses)[i].tail<3>() = x->t[i];
  const auto pose_block = [&](int i) { return i == 0 ? nullptr : (*poses)[i].data(); };
  const auto fixed_t = [&](int i) { return i == 0 ? &x->t[0] : nullptr; };
  const double pixel_sigma = 1 / std::sqrt(pixel_weight);
  for (int i = 0; i < num_frames(); ++i)
    for (const auto& o : frames[i].observations) {
      if (!index.count(o.track)) continue;
      const PointAnchor& anchor = anchors.at(o.track);
      PixelModel model = [&filter, &anchor](const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                                            const Eigen::Vector3d& point, bool jacobians,
                                            PixelPrediction* out) {
        Linearisation lin;
        if (!filter.linearise(anchor, R, t, at_placed_origin(point), jacobians, &lin)) return false;
        out->pixel = lin.pixel;
        if (jacobians) {
          out->pose = lin.pose;
          out->point = lin.point.leftCols<3>();
        }
        return true;
      };
      auto* cost = new StartPixelCost(std::move(model), &x->R[i], fixed_t(i), o.pixel, pixel_sigma);
      double* point = x->points.at(o.track).data();
      if (i == 0)
        problem->AddResidualBlock(cost, nullptr, point);
      else
        problem->AddResidualBlock(cost, nullptr, pose_block(i), point);
    }
  for (int i = 1; i < num_frames(); ++i) {
    auto* cost = new StartMotionCost({&x->R[i - 1], fixed_t(i - 1)}, {&x->R[i], nullptr},
                                     frames[i].random_walk ? nullptr : &frames[i].motion,
                                     motion_weight[i], sensor_jacobian[i],
                                     prior_sensors - predicted_at[i]);
    std::vector<double*> blocks;
    if (i > 1) blocks.push_back(pose_block(i - 1));
    blocks.push_back(pose_block(i));
    blocks.push_back(x->sensors.data());
    problem->AddResidualBlock(cost, nullptr, blocks);
  }
  problem->AddResidualBlock(
      new ceres::NormalPrior(Eigen::Matrix4d(sensor_prior_weight.cwiseSqrt().asDiagonal()),
                             Eigen::Vector4d::Zero()),
      nullptr, x->sensors.data());
  if (far_distance > 0)
    problem->AddResidualBlock(new StartScaleCost(far_distance, 1 / std::sqrt(scale_weight)),
                              nullptr, pose_block(far));
  Eigen::Matrix<double, 1, 3> depth_row(0, 0, std::sqrt(depth_weight));
  for (const auto& [track, column] : index) {
    double* point = x->points.at(track).data();
    problem->AddResidualBlock(
        new ceres::NormalPrior(depth_row, Eigen::Vector3d(0, 0, prior_depth)), nullptr, point);
    problem->SetParameterLowerBound(point, 2, kMinInverseDepth);
  }
}

std::vector<double*> OnlineFilter::StartWindow::blocks(StartEstimate* x,
                                                      std::vector<PoseBlock>* poses) const {
  std::vector<double*> blocks;
  for (int i = 1; i < num_frames(); ++i) blocks.push_back((*poses)[i].data());
  blocks.push_back(x->sensors.data());
  std::vector<double*> points(index.size());
  for (const auto& [track, column] : index) points[column] = x->points.at(track).data();
  blocks.insert(blocks.end(), points.begin(), points.end());
  return blocks;
}

Eigen::MatrixXd OnlineFilter::StartWindow::normal_equations(ceres::Problem* problem,
                                                            StartEstimate* x,
                                                            std::vector<PoseBlock>* poses) const {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = blocks(x, poses);
  ceres::CRSMatrix crs;
  if (!problem->Evaluate(options, nullptr, nullptr, nullptr, &crs)) return {};
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> J(
      crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()), crs.rows.data(),
      crs.cols.data(), crs.values.data());
  return Eigen::MatrixXd(J.transpose() * J);
}

OnlineFilter::StartWindow::Worst OnlineFilter::StartWindow::worst_pixel(
    const OnlineFilter& filter, const StartEstimate& x, bool with_median) const {
  Worst worst;
  std::vector<double> squared;
  for (int i = 0; i < num_frames(); ++i)
    for (const auto& o : frames[i].observations) {
      if (!index.count(o.track)) continue;
      Linearisation lin;
      if (!filter.linearise(anchors.at(o.track), x.R[i], x.t[i],
                            at_placed_origin(x.points.at(o.track)), false, &lin))
        continue;
      const double pixels = (lin.pixel - o.pixel).norm();
      if (with_median) squared.push_back(pixels * pixels);
      if (pixels > worst.pixels) worst = {pixels, o.track, frames[i].frame};
    }
  if (with_median) worst.median_squared_pixels = core::percentile(squared, 0.5);
  return worst;
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

bool OnlineFilter::solve_start_window(StartWindow* w, StartEstimate* x, Eigen::MatrixXd* A) {
  // Levenberg-Marquardt, then the paper's rejection on the window: while the worst residual
  // exceeds the threshold, that track goes and the rest is solved again.
  // Solved again when the noise measured on the solution reweighs the window's pixels, so that
  // the covariance is the solution's at the weight it was solved at; the noise taken has a gap
  // between taking and letting go, and a few rounds settle it.
  constexpr int kMaxReweighings = 3;
  int reweighings = 0;
  for (;;) {
    w->index.clear();
    for (const auto& [track, p] : x->points)
      if (!excluded_.count(track)) w->index.emplace(track, static_cast<int>(w->index.size()));
    ceres::Problem problem;
    std::vector<PoseBlock> poses;
    w->add_terms(*this, x, &poses, &problem);
    double cost = 0;
    // The filter's own estimate not projecting there, it is kept.
    if (!problem.Evaluate({}, &cost, nullptr, nullptr, nullptr)) return false;
    ceres::Solver::Summary summary;
    ceres::Solve(window_solver_options(), &problem, &summary);
    // The solution taken, and the problem re-centred on it (its costs hold x's rotations as
    // their references), so that its Jacobians are the filter's left perturbations there.
    for (int i = 1; i < w->num_frames(); ++i) {
      x->R[i] = rotation_of(poses[i].data(), x->R[i]);
      x->t[i] = poses[i].tail<3>();
      poses[i].head<3>().setZero();
    }
    const bool measure =
        settings_.measure_noise && settings_.outlier_test == OutlierTest::kChiSquare;
    const StartWindow::Worst worst = w->worst_pixel(*this, *x, measure);
    if (measure) {
      // The residuals' median norm, squared, is chi-square(2)'s median (2 ln 2) of the noise's
      // variance (a little less, for what the window fits); the window's pixels weighed at it.
      const double solved_weight = w->pixel_weight;
      take_noise(worst.median_squared_pixels / kChiSquare2Median /
                 (settings_.pixel_sigma * settings_.pixel_sigma));
      w->pixel_weight = 1 / (pixel_sigma() * pixel_sigma());
      if (w->pixel_weight != solved_weight && ++reweighings <= kMaxReweighings) continue;
    }
    if (!(worst.pixels > residual_limit_px())) {
      *A = w->normal_equations(&problem, x, &poses);
      return A->size() > 0;
    }
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
  state_.reset_considered_blocks();
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
