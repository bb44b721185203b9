#include "omnisfm/sfm/batch_adjustment.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <glog/logging.h>

#include <chrono>
#include <cmath>

#include "batch_terms.h"
#include "projection_cost.h"

namespace omnisfm::sfm {
namespace {

PoseVector to_vector(const Eigen::Isometry3d& T) {
  PoseVector v;
  const Eigen::Matrix3d R = T.linear();
  ceres::RotationMatrixToAngleAxis(ceres::ColumnMajorAdapter3x3(R.data()), v.data());
  v.tail<3>() = T.translation();
  return v;
}

Eigen::Isometry3d to_pose(const PoseVector& v) {
  Eigen::Matrix3d R;
  ceres::AngleAxisToRotationMatrix(v.data(), ceres::ColumnMajorAdapter3x3(R.data()));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = v.tail<3>();
  return T;
}

// Above this share of frame pairs observing a common point, the reduced camera system is dense.
constexpr double kDenseFill = 0.25;

// The share of frame pairs that observe a common point: the fill of the reduced camera system.
double reduced_system_fill(const std::vector<io::TrackObservation>& observations, int frames) {
  std::map<int, std::vector<int>> frames_of_track;
  std::vector<std::vector<int>> tracks_of_frame(frames);
  for (const auto& o : observations) {
    frames_of_track[o.track].push_back(o.frame);
    tracks_of_frame[o.frame].push_back(o.track);
  }
  std::vector<int> counted_for(frames, -1);
  double pairs = 0;
  for (int f = 0; f < frames; ++f)
    for (int track : tracks_of_frame[f])
      for (int g : frames_of_track[track])
        if (g <= f && counted_for[g] != f) {
          counted_for[g] = f;
          ++pairs;
        }
  return frames > 0 ? pairs / (0.5 * frames * (frames + 1.0)) : 0;
}

// Adds the reprojection residual of `o` on pose and point (and on the inverse scale, when given);
// nullptr, adding nothing, when the point cannot be projected from there.
ceres::ResidualBlockId add_reprojection(ceres::Problem* problem,
                                        const camera::CatadioptricCamera& camera,
                                        const io::TrackObservation& o, double huber_px,
                                        double* pose, double* point, double* inverse_scale) {
  ceres::CostFunction* cost = inverse_scale
                                  ? static_cast<ceres::CostFunction*>(
                                        new ScaledProjectionCost(&camera, o.pixel))
                                  : new ProjectionCost(&camera, o.pixel);
  double residual[2];
  const double* blocks[3] = {pose, point, inverse_scale};
  if (!cost->Evaluate(blocks, residual, nullptr)) {
    delete cost;
    return nullptr;
  }
  ceres::LossFunction* loss = huber_px > 0 ? new ceres::HuberLoss(huber_px) : nullptr;
  return inverse_scale ? problem->AddResidualBlock(cost, loss, pose, point, inverse_scale)
                       : problem->AddResidualBlock(cost, loss, pose, point);
}

// With the inverse scale free, its gauge: one translation coordinate held, the largest of the
// frame farthest from the first (which sits at the origin). False when every frame is there.
bool hold_scale_gauge(ceres::Problem* problem, std::vector<PoseVector>* poses) {
  double farthest = 0;
  PoseVector* held = nullptr;
  for (size_t f = 1; f < poses->size(); ++f) {
    PoseVector& pose = (*poses)[f];
    // |t| is the frame's distance from the origin: t = -R c.
    if (problem->HasParameterBlock(pose.data()) && pose.tail<3>().norm() > farthest) {
      farthest = pose.tail<3>().norm();
      held = &pose;
    }
  }
  if (!held || !(farthest > 0)) return false;
  int coordinate = 3;
  for (int i = 4; i < 6; ++i)
    if (std::abs((*held)[i]) > std::abs((*held)[coordinate])) coordinate = i;
  problem->SetManifold(held->data(), new ceres::SubsetManifold(6, {coordinate}));
  return true;
}

}  // namespace

BatchResult batch_adjust(const camera::CatadioptricCamera& camera,
                         const std::vector<io::TrackObservation>& observations,
                         const std::vector<Eigen::Isometry3d>& cam_from_world,
                         const std::map<int, Eigen::Vector3d>& start_points,
                         const BatchSettings& settings) {
  return batch_adjust(camera, observations, cam_from_world, start_points, settings, nullptr);
}

BatchResult batch_adjust(const camera::CatadioptricCamera& camera,
                         const std::vector<io::TrackObservation>& observations,
                         const std::vector<Eigen::Isometry3d>& cam_from_world,
                         const std::map<int, Eigen::Vector3d>& start_points,
                         const BatchSettings& settings, ExtraTerms* extra) {
  const auto started = std::chrono::steady_clock::now();
  FLAGS_minloglevel = std::max(FLAGS_minloglevel, google::GLOG_ERROR);
  BatchResult result;
  std::vector<PoseVector> poses;
  for (const auto& T : cam_from_world) poses.push_back(to_vector(T));
  std::map<int, Eigen::Vector3d> points = start_points;
  if (poses.empty()) {
    result.message = "no observation can be projected from the starting estimate";
    return result;
  }

  // Without motion sensors the scale is observed only through the mirror's noncentral parallax,
  // which falls as 1 / scale: in metric coordinates the cost is far from quadratic along the
  // scale, and from a start off in scale (a filter's) Levenberg-Marquardt takes a step per
  // halving of the error, its full Gauss-Newton steps overshooting off the mirror. Solved instead
  // for the inverse scale sigma and for poses and points in units of it, X = (R p + t) / sigma,
  // about the first camera's centre (which the held first pose keeps in place): the parallax is
  // then close to linear in sigma. The solution is the same, in a few iterations. Only where most
  // frames share points: along a long drive the scale drifts rather than being one number, and
  // sigma's dense row in the banded reduced system costs more than it saves.
  std::vector<io::TrackObservation> candidates;
  for (const auto& o : observations)
    if (points.count(o.track) && o.frame >= 0 && o.frame < static_cast<int>(poses.size()))
      candidates.push_back(o);
  const double fill = reduced_system_fill(candidates, static_cast<int>(poses.size()));
  const bool inverse_scale = !extra && fill > kDenseFill;
  const Eigen::Vector3d origin = to_pose(poses[0]).inverse().translation();
  if (inverse_scale) {
    for (auto& pose : poses) pose.tail<3>() += to_pose(pose).linear() * origin;
    for (auto& [track, p] : points) p -= origin;
  }
  double sigma = 1;

  ceres::Problem problem;
  std::vector<ceres::ResidualBlockId> projections;
  std::vector<io::TrackObservation> used_observations;
  for (const auto& o : candidates) {
    // Left out when it cannot be projected from the start.
    const ceres::ResidualBlockId id =
        add_reprojection(&problem, camera, o, settings.huber_px, poses[o.frame].data(),
                         points[o.track].data(), inverse_scale ? &sigma : nullptr);
    if (!id) continue;
    projections.push_back(id);
    used_observations.push_back(o);
  }
  const double used = static_cast<double>(used_observations.size());
  if (used == 0) {
    result.message = "no observation can be projected from the starting estimate";
    return result;
  }
  const bool gauge_fixed = extra && extra->add(&problem, &poses);
  if (!gauge_fixed && problem.HasParameterBlock(poses[0].data()))
    problem.SetParameterBlockConstant(poses[0].data());
  // Without a frame away from the first the scale has no gauge to measure it against (nor is it
  // observable): sigma stays 1.
  const bool scale_held_by_pose = inverse_scale && hold_scale_gauge(&problem, &poses);
  if (inverse_scale && !scale_held_by_pose) problem.SetParameterBlockConstant(&sigma);

  ceres::Solver::Options options;
  // Points are eliminated (Ceres' specialised 2 x 3 x 6 Schur kernels): they never share a
  // residual, extra terms included, so they are an independent set.
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (auto& [track, p] : points)
    if (problem.HasParameterBlock(p.data())) ordering->AddElementToGroup(p.data(), 0);
  std::vector<double*> blocks_in_problem;
  problem.GetParameterBlocks(&blocks_in_problem);
  for (double* block : blocks_in_problem)
    if (!ordering->IsMember(block)) ordering->AddElementToGroup(block, 1);
  options.linear_solver_ordering = ordering;
  if (fill > kDenseFill) {
    // When most frames share points (short sequences, long tracks) the reduced camera system is
    // dense, and forming and factoring it costs more than the whole evaluation. Conjugate
    // gradients on it, with its block diagonal as preconditioner, never form it; a small forcing
    // term keeps the steps as good as a direct solve's, so Levenberg-Marquardt takes as many.
    options.linear_solver_type = ceres::ITERATIVE_SCHUR;
    options.preconditioner_type = ceres::SCHUR_JACOBI;
    options.eta = 1e-6;
  } else {
    // Long sequences: frames share points with their neighbours only, the reduced system is
    // banded and a sparse Cholesky solves it exactly, where conjugate gradients would need
    // thousands of iterations along the drive's slow deformations.
    options.linear_solver_type = ceres::SPARSE_SCHUR;
  }
  // The start (the filter's estimate) is close: begin near Gauss-Newton. Ceres' default radius
  // damps the weakly observed scale so hard that it takes a dozen iterations to release it.
  options.initial_trust_region_radius = 1e7;
  options.max_num_iterations = settings.max_iterations;
  options.num_threads = 2;
  options.logging_type = ceres::SILENT;
  // Converged when a step lowers chi-square by less than 0.01, i.e. moves the estimate by less
  // than a tenth of its standard deviation (the pixel variance taken from the cost). A fixed
  // relative tolerance instead lets Levenberg-Marquardt creep for hundreds of iterations along a
  // long drive's slow, curved deformations without changing anything that can be measured.
  // Degrees of freedom: residuals less free parameters (NumParameters counts a held first pose,
  // sigma, and the translation coordinate or sigma held for sigma's gauge).
  const double held = (gauge_fixed ? 0 : 6) + (inverse_scale ? 1 : 0);
  const double dof = std::max(1.0, 1.0 * problem.NumResiduals() - problem.NumParameters() + held);
  options.function_tolerance = std::max(1e-10, 0.01 / dof);
  options.parameter_tolerance = 1e-10;
  // With extra residuals, the pixel figures are the reprojections' share of the cost alone.
  const auto reprojection_cost = [&] {
    ceres::Problem::EvaluateOptions reprojections;
    reprojections.residual_blocks = projections;
    double cost = 0;
    problem.Evaluate(reprojections, &cost, nullptr, nullptr, nullptr);
    return cost;
  };
  const double initial_reprojection_cost = extra ? reprojection_cost() : 0;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.message = summary.message;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.initial_rms_px = std::sqrt(summary.initial_cost / used);
  result.final_rms_px = std::sqrt(summary.final_cost / used);
  if (extra) {
    result.initial_rms_px = std::sqrt(initial_reprojection_cost / used);
    result.final_rms_px = std::sqrt(reprojection_cost() / used);
  }
  result.solve_seconds = summary.total_time_in_seconds;
  result.linear_solver = ceres::LinearSolverTypeToString(summary.linear_solver_type_used);
  if (inverse_scale) {
    for (auto& pose : poses)
      pose.tail<3>() = pose.tail<3>() / sigma - to_pose(pose).linear() * origin;
    for (auto& [track, p] : points) p = p / sigma + origin;
  }
  for (const auto& v : poses) result.cam_from_world.push_back(to_pose(v));
  result.points = points;

  // Covariances of the metric poses and points: from the same reprojections on them, the first
  // pose held.
  ceres::Problem metric_problem;
  if (inverse_scale && settings.covariances && summary.IsSolutionUsable()) {
    for (const auto& o : used_observations)
      add_reprojection(&metric_problem, camera, o, settings.huber_px, poses[o.frame].data(),
                       points[o.track].data(), nullptr);
    if (metric_problem.HasParameterBlock(poses[0].data()))
      metric_problem.SetParameterBlockConstant(poses[0].data());
  }
  ceres::Problem& problem_on_poses = inverse_scale ? metric_problem : problem;
  if (settings.covariances && summary.IsSolutionUsable()) {
    ceres::Covariance::Options covariance_options;
    // Sparse QR: the gauge is fixed by the first pose, so the problem is of full rank.
    covariance_options.algorithm_type = ceres::SPARSE_QR;
    covariance_options.num_threads = 2;
    ceres::Covariance covariance(covariance_options);
    std::vector<std::pair<const double*, const double*>> blocks;
    for (const auto& v : poses)
      if (problem_on_poses.HasParameterBlock(v.data()) && !problem_on_poses.IsParameterBlockConstant(v.data()))
        blocks.emplace_back(v.data(), v.data());
    for (const auto& [track, p] : points)
      if (problem_on_poses.HasParameterBlock(p.data())) blocks.emplace_back(p.data(), p.data());
    if (covariance.Compute(blocks, &problem_on_poses)) {
      // Scaled by the residual variance: the pixel noise is estimated, not assumed.
      const double variance = 2 * summary.final_cost / dof;
      result.pose_covariances.assign(poses.size(), Eigen::Matrix<double, 6, 6>::Zero());
      for (size_t f = 0; f < poses.size(); ++f) {
        if (!problem_on_poses.HasParameterBlock(poses[f].data()) ||
            problem_on_poses.IsParameterBlockConstant(poses[f].data()))
          continue;
        Eigen::Matrix<double, 6, 6, Eigen::RowMajor> c;
        covariance.GetCovarianceBlock(poses[f].data(), poses[f].data(), c.data());
        result.pose_covariances[f] = variance * c;
      }
      for (const auto& [track, p] : points) {
        if (!problem_on_poses.HasParameterBlock(p.data())) continue;
        Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c;
        covariance.GetCovarianceBlock(p.data(), p.data(), c.data());
        result.point_covariances[track] = variance * c;
      }
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

ceres::CostFunction* make_projection_cost(const camera::CatadioptricCamera* camera,
                                          const Eigen::Vector2d& pixel) {
  return new ProjectionCost(camera, pixel);
}

}  // namespace omnisfm::sfm
