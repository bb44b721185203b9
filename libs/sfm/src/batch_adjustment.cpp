#include "omnisfm/sfm/batch_adjustment.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

#include "batch_terms.h"
#include "camera_refinement.h"
#include "marginal_variance.h"
#include "omnisfm/core/pose_direction.h"
#include "omnisfm/core/solver_threads.h"
#include "projection_cost.h"
#include "track_points.h"

namespace omnisfm::sfm {
namespace {

using core::isometry_of;
using core::pose_vector_of;

// The share of frame pairs that observe a common point: the fill of the reduced camera system.
// Each frame's row is the union of its tracks' frame sets, as bit sets.
double reduced_system_fill(const std::vector<core::TrackObservation>& observations, int frames) {
  if (frames <= 0) return 0;
  const size_t words = (static_cast<size_t>(frames) + 63) / 64;
  std::map<int, int> track_index;
  for (const auto& o : observations)
    track_index.emplace(o.track, static_cast<int>(track_index.size()));
  std::vector<uint64_t> frames_of_track(track_index.size() * words, 0);
  std::vector<std::vector<int>> tracks_of_frame(frames);
  for (const auto& o : observations) {
    const int track = track_index.at(o.track);
    frames_of_track[track * words + o.frame / 64] |= uint64_t{1} << (o.frame % 64);
    tracks_of_frame[o.frame].push_back(track);
  }
  std::vector<uint64_t> row(words);
  double pairs = 0;
  for (int f = 0; f < frames; ++f) {
    std::fill(row.begin(), row.end(), 0);
    for (int track : tracks_of_frame[f])
      for (size_t w = 0; w < words; ++w) row[w] |= frames_of_track[track * words + w];
    // Frames g <= f only: the pairs of the lower triangle.
    for (size_t w = 0; w <= static_cast<size_t>(f) / 64; ++w) {
      const int last_bit = w == static_cast<size_t>(f) / 64 ? f % 64 : 63;
      const uint64_t mask = last_bit == 63 ? ~uint64_t{0} : (uint64_t{1} << (last_bit + 1)) - 1;
      pairs += __builtin_popcountll(row[w] & mask);
    }
  }
  return pairs / (0.5 * frames * (frames + 1.0));
}

// Which observations project from the start (the others are left out of the problem): a
// projection each, on two threads when there are threads to spare.
std::vector<char> projectable(const camera::CatadioptricCamera& camera,
                              const std::vector<core::TrackObservation>& observations,
                              const std::vector<PoseVector>& poses, const TrackPoints& points,
                              int threads) {
  std::vector<char> ok(observations.size(), 0);
  const auto check = [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const auto& o = observations[i];
      const Eigen::Vector3d* point = points.find(o.track);
      if (!point || o.frame < 0 || o.frame >= static_cast<int>(poses.size())) continue;
      double residual[2];
      ok[i] = evaluate_projection(camera, o.pixel, poses[o.frame].data(), point->data(), 1,
                                  residual, nullptr, nullptr, nullptr);
    }
  };
  if (threads < 2) {
    check(0, observations.size());
    return ok;
  }
  const size_t half = observations.size() / 2;
  std::thread helper(check, 0, half);
  check(half, observations.size());
  helper.join();
  return ok;
}

// Points are eliminated (Ceres' specialised 2 x 3 x 6 Schur kernels): they never share a residual,
// extra terms included, so they are an independent set. Then the poses, then the rest (the camera,
// the sensors' states). Ceres orders each group by address: the points and the poses are one
// array each, and apart they keep the order from depending on where the heap put the camera.
std::shared_ptr<ceres::ParameterBlockOrdering> points_eliminated_first(
    const ceres::Problem& problem, TrackPoints* points, std::vector<PoseVector>* poses) {
  auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
  for (auto& [track, p] : *points)
    if (problem.HasParameterBlock(p.data())) ordering->AddElementToGroup(p.data(), 0);
  for (PoseVector& pose : *poses)
    if (problem.HasParameterBlock(pose.data())) ordering->AddElementToGroup(pose.data(), 1);
  std::vector<double*> blocks;
  problem.GetParameterBlocks(&blocks);
  for (double* block : blocks)
    if (!ordering->IsMember(block)) ordering->AddElementToGroup(block, 2);
  return ordering;
}

// The world scaled by k about the first camera's centre c0: p' = c0 + k (p - c0) and
// t' = k t + R c0 (k - 1), which keeps the first pose.
void scale_about_first_camera(double k, std::vector<PoseVector>* poses, TrackPoints* points) {
  const Eigen::Isometry3d first = isometry_of((*poses)[0]);
  const Eigen::Vector3d c0 = -first.linear().transpose() * first.translation();
  for (size_t f = 1; f < poses->size(); ++f) {
    Eigen::Isometry3d T = isometry_of((*poses)[f]);
    T.translation() = k * T.translation() + T.linear() * c0 * (k - 1);
    (*poses)[f] = pose_vector_of(T);
  }
  for (auto& [track, p] : *points) p = c0 + k * (p - c0);
}

// How far camera f is from the first.
double distance_from_first(const std::vector<PoseVector>& poses, size_t f) {
  return (isometry_of(poses[f]).inverse().translation() - isometry_of(poses[0]).inverse().translation())
      .norm();
}

// Element by element: the problem holds the addresses of these values.
void restore(const std::vector<PoseVector>& start_poses, const TrackPoints& start_points,
             std::vector<PoseVector>* poses, TrackPoints* points) {
  std::copy(start_poses.begin(), start_poses.end(), poses->begin());
  for (auto& [track, p] : *points) p = start_points.at(track);
}

// With the first pose held, what else fixes the scale: the translation coordinate farthest from
// the first pose's on any other pose in the problem. None (null) when no camera moved.
struct ScaleGauge {
  double* pose = nullptr;
  int frame = 0;
  int coordinate = 0;
};

ScaleGauge scale_gauge(const ceres::Problem& problem, std::vector<PoseVector>* poses) {
  ScaleGauge gauge;
  double farthest = 0;
  for (size_t f = 1; f < poses->size(); ++f)
    for (int k = 3; k < 6; ++k)
      if (problem.HasParameterBlock((*poses)[f].data()) &&
          std::abs((*poses)[f][k] - (*poses)[0][k]) > farthest) {
        farthest = std::abs((*poses)[f][k] - (*poses)[0][k]);
        gauge = {(*poses)[f].data(), static_cast<int>(f), k};
      }
  return gauge;
}

void hold(ceres::Problem* problem, const ScaleGauge& gauge) {
  problem->SetManifold(gauge.pose, new ceres::SubsetManifold(6, {gauge.coordinate}));
}

// The relative standard deviation of the scene's scale at the estimate `problem` holds: the
// marginal standard deviation of the inverse scale u (at 1) with the gauge's coordinate held,
// times sqrt(variance). Infinite when the information is singular: nothing fixes the scale.
double scale_sigma_relative(ceres::Problem* problem, const ScaleGauge& gauge, double* u,
                            TrackPoints* points, double variance) {
  hold(problem, gauge);
  problem->SetParameterBlockVariable(u);
  std::vector<double*> point_blocks;
  for (auto& [track, p] : *points) point_blocks.push_back(p.data());
  const double sigma = std::sqrt(variance * marginal_variance(problem, u, point_blocks)) / *u;
  problem->SetParameterBlockConstant(u);
  problem->SetManifold(gauge.pose, nullptr);
  return std::isnan(sigma) ? INFINITY : sigma;
}

// The solve with the scene's inverse scale u as a parameter of its own, the camera-frame points
// being (R p + t) / u. The scale is weakly observed (through the mirror's size) and the filter's
// can be far off while its shape is right: the rover starts with a 17.6 m path for 3.45 m. Along
// the translations and points the residuals are far from linear in the scale, and Levenberg-
// Marquardt walked it for most of its iterations (5 of 8), each step held back by the trust region
// or refused; in u they are nearly linear (scaling the scene by s is scaling the mirror by 1/s),
// and the rover converges in 2 steps. The gauge: the first pose held (by the caller), and also
// scale_gauge's coordinate, which u then scales. On return u is 1 and held constant, and `problem`
// is the plain one again: with the solve's minimum, written with the first pose unchanged, when it
// moved the estimate; with the start otherwise.
struct ScaleSolve {
  bool solved = false;     // it ran Ceres (summary is its)
  bool converged = false;  // and it is the plain problem's minimum too
};

ScaleSolve solve_with_scale(ceres::Problem* problem, ceres::Solver::Options options,
                            std::vector<PoseVector>* poses, TrackPoints* points, double* u,
                            ceres::Solver::Summary* summary) {
  // Beyond it the scene has run toward infinity or collapsed: the data hold no scale.
  constexpr double kScaleRange = 1000;
  const ScaleGauge gauge = scale_gauge(*problem, poses);
  if (!gauge.pose) return {};  // no motion: no scale to find
  const std::vector<PoseVector> start_poses = *poses;
  const TrackPoints start_points = *points;
  hold(problem, gauge);
  problem->SetParameterBlockVariable(u);
  // The plain problem's forcing term is for its slow scale direction. With the scale a parameter,
  // 1e-3 takes as many steps to the same cost, with 15-20 conjugate gradient iterations, not 25.
  options.eta = 1e-3;
  ceres::Solve(options, problem, summary);
  problem->SetManifold(gauge.pose, nullptr);
  problem->SetParameterBlockConstant(u);
  const double scale = *u;
  *u = 1;
  if (!summary->IsSolutionUsable() || !(summary->final_cost < summary->initial_cost) ||
      !(scale > 1 / kScaleRange && scale < kScaleRange)) {
    restore(start_poses, start_points, poses, points);
    return {true, false};
  }
  // Written in the plain problem's terms, which keeps every camera-frame point.
  scale_about_first_camera(1 / scale, poses, points);
  return {true, summary->termination_type == ceres::CONVERGENCE};
}

// A known distance between the first and last cameras scales the start only when they are well
// apart in it: at least this share of the farthest camera's distance from the first.
constexpr double kMinKnownDistanceShare = 0.05;

// The factor that puts the first and last cameras known_distance_m apart in `poses`, or the
// reason it cannot.
struct KnownDistanceFactor {
  double factor = 1;
  std::string problem;
};

KnownDistanceFactor known_distance_factor(const std::vector<PoseVector>& poses,
                                          double known_distance_m) {
  std::ostringstream why;
  if (!(known_distance_m > 0 && std::isfinite(known_distance_m))) {
    why << "the known distance must be a finite number of metres above 0, not " << known_distance_m;
    return {1, why.str()};
  }
  double farthest = 0;
  for (size_t f = 1; f < poses.size(); ++f)
    farthest = std::max(farthest, distance_from_first(poses, f));
  const double distance = distance_from_first(poses, poses.size() - 1);
  if (!(distance >= kMinKnownDistanceShare * farthest) || !(distance > 0)) {
    why << "the first and last cameras are " << distance << " apart in the start, where the "
        << "farthest camera is " << farthest << " from the first: too close for the known "
        << "distance between them to fix the scale";
    return {1, why.str()};
  }
  return {known_distance_m / distance, ""};
}

}  // namespace

// On the rover, seed 2, one point's reflection sits at the rim: with the exact patch 11 of 16
// iterations were refused, and the estimate stayed at the filter's scale.
// One reprojection residual per observation, on its frame's pose, its track's point and the
// inverse scale.
// With `shared` (the camera block's camera), the residuals also take the camera block.
std::vector<ceres::ResidualBlockId> add_projections(
    const camera::CatadioptricCamera& camera, const std::vector<core::TrackObservation>& used,
    const BatchSettings& settings, bool with_extra_terms, std::vector<PoseVector>* poses,
    TrackPoints* points, double* inverse_scale, const camera::SharedCamera* shared,
    double* camera_block, ceres::Problem* problem) {
  const double pixel_weight = 1 / (settings.pixel_sigma * settings.pixel_sigma);
  std::vector<ceres::ResidualBlockId> projections;
  for (const auto& o : used) {
    ceres::LossFunction* loss =
        settings.huber_px > 0 ? new ceres::HuberLoss(settings.huber_px) : nullptr;
    // Against the sensors' whitened terms the pixels weigh as their noise says; alone, a weight
    // would change only the cost's units.
    if (with_extra_terms) loss = new ceres::ScaledLoss(loss, pixel_weight, ceres::TAKE_OWNERSHIP);
    if (shared)
      projections.push_back(problem->AddResidualBlock(
          new RefinedProjectionCost(shared, o.pixel), loss, (*poses)[o.frame].data(),
          points->at(o.track).data(), inverse_scale, camera_block));
    else
      projections.push_back(problem->AddResidualBlock(
          new ScaledProjectionCost(&camera, o.pixel), loss, (*poses)[o.frame].data(),
          points->at(o.track).data(), inverse_scale));
  }
  return projections;
}

// The camera block (BatchSettings::camera_prior), the parameters not refined held.
void add_camera_block(const camera::CatadioptricCamera& camera, const BatchSettings& settings,
                     double* camera_block, ceres::Problem* problem) {
  const std::vector<int>& refined = settings.camera_prior.parameters;
  const int size = camera.num_params();
  std::vector<int> held;
  for (int i = 0; i < size; ++i)
    if (std::find(refined.begin(), refined.end(), i) == refined.end()) held.push_back(i);
  problem->AddParameterBlock(camera_block, size,
                             held.empty() ? nullptr : new ceres::SubsetManifold(size, held));
}

// The camera refined in a last solve under the calibration's prior, weighed by pixel_sigma
// (CameraPriorCost), from where the scale's solves left the problem. False when that solve's
// result is not usable: the poses, points and camera are then put back and the camera held again.
bool refine_camera_last(ceres::Problem* problem, ceres::Solver::Options options,
                        const camera::CatadioptricCamera& calibrated, const CameraPrior& prior,
                        double pixel_sigma, double* camera_block, std::vector<PoseVector>* poses,
                        TrackPoints* points, ceres::Solver::Summary* summary) {
  const std::vector<PoseVector> saved_poses = *poses;
  const TrackPoints saved_points = *points;
  problem->AddResidualBlock(
      new CameraPriorCost(calibrated.params(), prior.parameters, prior.covariance, pixel_sigma),
      nullptr, camera_block);
  problem->SetParameterBlockVariable(camera_block);
  // Ceres drops held blocks from the ordering it is given: the camera's goes back in.
  options.linear_solver_ordering = points_eliminated_first(*problem, points, poses);
  ceres::Solve(options, problem, summary);
  if (summary->IsSolutionUsable()) return true;
  restore(saved_poses, saved_points, poses, points);
  const Eigen::VectorXd params = calibrated.params();
  std::copy(params.data(), params.data() + params.size(), camera_block);
  problem->SetParameterBlockConstant(camera_block);
  return false;
}

// The batch's problem in Ceres: the linear solver by how densely frames share points, the
// stopping rule in chi-square. `dof`: residuals less free parameters.
ceres::Solver::Options batch_solver_options(ceres::Problem* problem, TrackPoints* points,
                                            std::vector<PoseVector>* poses,
                                            const std::vector<core::TrackObservation>& used,
                                            int num_poses, const BatchSettings& settings,
                                            int threads, double dof) {
  ceres::Solver::Options options;
  options.linear_solver_ordering = points_eliminated_first(*problem, points, poses);
  const double fill = reduced_system_fill(used, num_poses);
  if (fill > 0.25) {
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
  options.num_threads = threads;
  options.logging_type = ceres::SILENT;
  // Converged when a step lowers chi-square by less than 0.01, i.e. moves the estimate by less
  // than a tenth of its standard deviation (the pixel variance taken from the cost). A fixed
  // relative tolerance instead lets Levenberg-Marquardt creep for hundreds of iterations along a
  // long drive's slow, curved deformations without changing anything that can be measured.
  options.function_tolerance = std::max(1e-10, 0.01 / dof);
  options.parameter_tolerance = 1e-10;
  return options;
}

// The degrees of freedom of the batch's chi-square: residuals less free parameters (NumParameters
// counts a held first pose, the inverse scale, held outside solve_with_scale, and the camera
// block, held while this is counted; refined later, its free values come with as many residuals
// of the prior).
double degrees_of_freedom(const ceres::Problem& problem, bool gauge_fixed, int held_camera) {
  const double held = (gauge_fixed ? 0 : 6) + 1 + held_camera;
  return std::max(1.0, 1.0 * problem.NumResiduals() - problem.NumParameters() + held);
}

// The solution's poses and the points the problem held: a start point whose observations were all
// left out was not adjusted, and its track is not the batch's.
void take_estimates(const ceres::Problem& problem, const std::vector<PoseVector>& poses,
                    const TrackPoints& points, BatchResult* result) {
  for (const auto& v : poses) {
    result->world_from_cam.push_back(isometry_of(v).inverse());
    result->cam_from_world_parameters.push_back(v);
  }
  for (const auto& [track, p] : points)
    if (problem.HasParameterBlock(p.data())) result->points[track] = p;
}

// The solution's covariances into `result`: the poses, consecutive poses, points, each point
// with the poses that saw it (when asked), and the extra terms' blocks.
void compute_covariances(ceres::Problem* problem, const std::vector<PoseVector>& poses,
                         const TrackPoints& points,
                         const std::vector<core::TrackObservation>& used_observations,
                         const BatchSettings& settings, ExtraTerms* extra, double* camera_block,
                         int threads, BatchResult* result) {
  ceres::Covariance::Options covariance_options;
  // Sparse QR: the gauge is fixed by the first pose (and the scale, when held, by a coordinate
  // of a far one), so the problem is of full rank.
  covariance_options.algorithm_type = ceres::SPARSE_QR;
  covariance_options.num_threads = threads;
  ceres::Covariance covariance(covariance_options);
  std::vector<std::pair<const double*, const double*>> blocks;
  const auto variable = [&](const PoseVector& v) {
    return problem->HasParameterBlock(v.data()) && !problem->IsParameterBlockConstant(v.data());
  };
  for (size_t f = 0; f < poses.size(); ++f) {
    if (!variable(poses[f])) continue;
    blocks.emplace_back(poses[f].data(), poses[f].data());
    if (f + 1 < poses.size() && variable(poses[f + 1]))
      blocks.emplace_back(poses[f].data(), poses[f + 1].data());
  }
  for (const auto& [track, p] : points)
    if (problem->HasParameterBlock(p.data())) blocks.emplace_back(p.data(), p.data());
  std::set<std::pair<int, int>> seen_from;  // (track, frame)
  if (settings.point_cam_from_world_covariances)
    for (const auto& o : used_observations) {
      const Eigen::Vector3d* point = points.find(o.track);
      if (!point || !problem->HasParameterBlock(point->data()) || !variable(poses[o.frame]) ||
          !seen_from.emplace(o.track, o.frame).second)
        continue;
      blocks.emplace_back(point->data(), poses[o.frame].data());
    }
  std::vector<std::pair<double*, int>> extra_blocks;
  if (extra)
    for (const auto& [block, size] : extra->blocks_with_covariance())
      if (problem->HasParameterBlock(block) && !problem->IsParameterBlockConstant(block)) {
        extra_blocks.emplace_back(block, size);
        blocks.emplace_back(block, block);
      }
  if (camera_block) blocks.emplace_back(camera_block, camera_block);
  if (covariance.Compute(blocks, problem)) {
    // Alone, scaled by the residual variance: the pixel noise is estimated, not assumed. With
    // the sensors' terms every residual is whitened by its stated noise model, which is taken
    // as it is (the pixels' from pixel_sigma).
    const double variance = extra ? 1 : result->variance_factor;
    result->cam_from_world_covariances.assign(poses.size(), Eigen::Matrix<double, 6, 6>::Zero());
    result->consecutive_cam_from_world_covariances.assign(poses.empty() ? 0 : poses.size() - 1,
                                                          Eigen::Matrix<double, 6, 6>::Zero());
    for (size_t f = 0; f < poses.size(); ++f) {
      if (!variable(poses[f])) continue;
      Eigen::Matrix<double, 6, 6, Eigen::RowMajor> c;
      covariance.GetCovarianceBlock(poses[f].data(), poses[f].data(), c.data());
      result->cam_from_world_covariances[f] = variance * c;
      if (f + 1 < poses.size() && variable(poses[f + 1])) {
        covariance.GetCovarianceBlock(poses[f].data(), poses[f + 1].data(), c.data());
        result->consecutive_cam_from_world_covariances[f] = variance * c;
      }
    }
    for (const auto& [track, p] : points) {
      if (!problem->HasParameterBlock(p.data())) continue;
      Eigen::Matrix<double, 3, 3, Eigen::RowMajor> c;
      covariance.GetCovarianceBlock(p.data(), p.data(), c.data());
      result->point_covariances[track] = variance * c;
    }
    for (const auto& [track, frame] : seen_from) {
      Eigen::Matrix<double, 3, 6, Eigen::RowMajor> c;
      covariance.GetCovarianceBlock(points.at(track).data(), poses[frame].data(), c.data());
      result->point_cam_from_world_covariances[{track, frame}] = variance * c;
    }
    if (camera_block) {
      const int size = problem->ParameterBlockSize(camera_block);
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(size, size);
      covariance.GetCovarianceBlock(camera_block, camera_block, c.data());
      const std::vector<int>& refined = settings.camera_prior.parameters;
      const int k = static_cast<int>(refined.size());
      result->camera_covariance.resize(k, k);
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j)
          result->camera_covariance(i, j) = variance * c(refined[i], refined[j]);
    }
    for (const auto& [block, size] : extra_blocks) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> c(size, size);
      covariance.GetCovarianceBlock(block, block, c.data());
      extra->take_covariance(block, variance * Eigen::MatrixXd(c));
    }
  }
}

camera::CatadioptricCamera batch_camera(const camera::CatadioptricCamera& camera) {
  constexpr double kWidening = 0.1;
  std::unique_ptr<camera::MirrorProfile> mirror = camera.mirror().clone();
  const double margin = kWidening * (mirror->s_max() - mirror->s_min());
  if (!mirror->set_valid_range(std::max(0.0, mirror->s_min() - margin), mirror->s_max() + margin))
    return camera;
  return camera::CatadioptricCamera(camera.inner().clone(), std::move(mirror),
                                    camera.mirror_pose(), camera.image_width(),
                                    camera.image_height());
}

BatchResult batch_adjust(const camera::CatadioptricCamera& camera,
                         const std::vector<core::TrackObservation>& observations,
                         const std::vector<Eigen::Isometry3d>& start_world_from_cam,
                         const std::map<int, Eigen::Vector3d>& start_points,
                         const BatchSettings& settings) {
  return batch_adjust_with_terms(camera, observations, core::inverted(start_world_from_cam),
                                 start_points, settings, nullptr);
}

// The problem, its options, the solves and the covariances are steps of their own; the scale's
// sequence of solves (with the scale free, plain, then held where the images do not fix it)
// stays in one body, as it moves the problem's blocks between the solves and counts them.
namespace {

// What batch_adjust's steps share: the parameter blocks, the problem over them, and the solves'
// tally. Ceres holds pointers into it: it stays where it was made.
struct BatchProblem {
  std::vector<PoseVector> poses;
  TrackPoints points;
  // The scene's inverse scale: a parameter only while solve_with_scale runs, 1 and held otherwise.
  double inverse_scale = 1;
  Eigen::VectorXd camera_block;
  // With the camera a block, the residuals project with it at that block's values.
  std::unique_ptr<camera::SharedCamera> shared;
  std::unique_ptr<ceres::Problem> problem;
  std::vector<ceres::ResidualBlockId> projections;
  ceres::Solver::Options options;
  ceres::Solver::Summary summary;  // the last solve's that counts
  int iterations = 0;
  double solve_seconds = 0, initial_cost = -1;

  void count(const ceres::Solver::Summary& solve) {
    iterations += static_cast<int>(solve.iterations.size());
    solve_seconds += solve.total_time_in_seconds;
    if (initial_cost < 0) initial_cost = solve.initial_cost;  // the start's, of the first solve
  }
  void solve() {
    ceres::Solve(options, problem.get(), &summary);
    count(summary);
  }
  // The reprojections' share of the cost, in pixels (the sensors' terms weigh them by
  // pixel_weight, given with them; else 0).
  double reprojection_cost(double pixel_weight) const {
    ceres::Problem::EvaluateOptions reprojections;
    reprojections.residual_blocks = projections;
    double cost = 0;
    problem->Evaluate(reprojections, &cost, nullptr, nullptr, nullptr);
    return pixel_weight > 0 ? cost / pixel_weight : cost;
  }
};

// Where the start was, which a scale held at it goes back to.
struct BatchStart {
  std::vector<PoseVector> poses;
  TrackPoints points;
  KnownDistanceFactor known;
};

// Where the images' solve leaves the scale (result's scale_source and scale_sigma_relative): free
// where they fix it, else held, at the known distance or the start's, and solved again so.
// Returns the degrees of freedom the pixels' variance is then estimated with. `moves`: whether any
// camera moved from the first in the start.
double decide_scale(BatchProblem* b, const BatchStart& start, const BatchSettings& settings,
                    bool extra, bool moves, double dof, BatchResult* result) {
  const ScaleGauge gauge = scale_gauge(*b->problem, &b->poses);
  if (!moves || !gauge.pose) return dof;
  // Alone, the pixels' variance is estimated from the residuals, as for the covariances.
  const double variance = extra ? 1 : 2 * b->summary.final_cost / dof;
  result->scale_sigma_relative =
      scale_sigma_relative(b->problem.get(), gauge, &b->inverse_scale, &b->points, variance);
  const bool known = settings.known_distance_m > 0;
  if (known)
    result->scale_source = BatchScale::kHeldAtKnownDistance;
  else if (result->scale_sigma_relative <= settings.max_free_scale_sigma)
    result->scale_source = BatchScale::kFromImages;
  else
    result->scale_source = BatchScale::kHeldAtStart;
  if (result->scale_source == BatchScale::kFromImages) return dof;
  // From the images' minimum, its shape kept and its scale put back where it is held: the
  // start's (the gauge camera as far from the first as there) or the known distance between the
  // first and last cameras. Then the scale is held, and the solve takes a few steps (from the
  // start again it took as many as the first; on long drives 10 more).
  double factor = known ? settings.known_distance_m /
                              distance_from_first(b->poses, b->poses.size() - 1)
                        : distance_from_first(start.poses, gauge.frame) /
                              distance_from_first(b->poses, gauge.frame);
  if (!(std::isfinite(factor) && factor > 0)) {
    restore(start.poses, start.points, &b->poses, &b->points);
    factor = start.known.factor;
  }
  scale_about_first_camera(factor, &b->poses, &b->points);
  hold(b->problem.get(), gauge);
  b->solve();
  return dof + 1;
}

// The camera refined in a last solve under its calibration's prior, where the scale is known
// (where the images do not fix it, it is held at the start's, and the mirror's size would take
// up the difference); with the images' scale, its standard deviation again with the camera free.
void refine_camera_where_scale_known(BatchProblem* b, const camera::CatadioptricCamera& optimised,
                                     const CameraPrior& prior, bool extra, double variance_dof,
                                     BatchResult* result) {
  const bool scale_known = result->scale_source == BatchScale::kFromImages ||
                           result->scale_source == BatchScale::kHeldAtKnownDistance ||
                           result->scale_source == BatchScale::kFromSensors;
  if (!scale_known) return;
  // The calibration's prior against the pixels: whitened with them by the sensors' terms, else
  // in pixels at the noise the solve so far has found in them (not the stated one: the prior
  // would weigh as much more as the stated noise is larger). The covariances later take the
  // noise after this solve, which the calibration's error hardly changes (rover: 0.19589 and
  // 0.19585 px).
  const double pixel_sigma = extra ? 1 : std::sqrt(2 * b->summary.final_cost / variance_dof);
  ceres::Solver::Summary refining;
  result->camera_refined =
      refine_camera_last(b->problem.get(), b->options, optimised, prior, pixel_sigma,
                         b->camera_block.data(), &b->poses, &b->points, &refining);
  b->count(refining);
  if (result->camera_refined) b->summary = refining;
  // The images' scale was decided with the camera as calibrated; what the data fix once the
  // camera's own uncertainty is admitted is the scale's standard deviation now (on the rover
  // 16-31 % against 7-14 %, and the calibrated camera's scales were off by up to 39 %).
  if (result->camera_refined && result->scale_source == BatchScale::kFromImages) {
    result->scale_sigma_relative_camera_held = result->scale_sigma_relative;
    result->scale_sigma_relative = scale_sigma_relative(
        b->problem.get(), scale_gauge(*b->problem, &b->poses), &b->inverse_scale, &b->points,
        extra ? 1 : 2 * b->summary.final_cost / variance_dof);
  }
}

// The solves' figures and estimates into `result`: the pixels' RMS from `initial_cost` (the
// reprojections' at the start) and at the end over `used` observations, the reprojections' alone
// where other residuals are in the problem (the sensors' terms, which weigh the pixels by
// `pixel_weight`, 0 without them; the camera's prior).
void take_solution(const BatchProblem& b, double initial_cost, double pixel_weight, double used,
                   double variance_dof, BatchResult* result) {
  const ceres::Solver::Summary& summary = b.summary;
  result->converged = summary.termination_type == ceres::CONVERGENCE;
  result->message = summary.message;
  result->iterations = b.iterations;
  result->initial_rms_px = std::sqrt(initial_cost / used);
  result->final_rms_px = std::sqrt(
      (pixel_weight > 0 || result->camera_refined ? b.reprojection_cost(pixel_weight)
                                                  : summary.final_cost) /
      used);
  result->solve_seconds = b.solve_seconds;
  result->variance_factor = 2 * summary.final_cost / variance_dof;
  result->linear_solver = ceres::LinearSolverTypeToString(summary.linear_solver_type_used);
  take_estimates(*b.problem, b.poses, b.points, result);
  if (result->camera_refined) result->camera_params = b.camera_block;
}

}  // namespace

BatchResult batch_adjust_with_terms(const camera::CatadioptricCamera& camera,
                                    const std::vector<core::TrackObservation>& observations,
                                    const std::vector<Eigen::Isometry3d>& start_cam_from_world,
                                    const std::map<int, Eigen::Vector3d>& start_points,
                                    const BatchSettings& settings, ExtraTerms* extra) {
  const auto started = std::chrono::steady_clock::now();
  BatchResult result;
  BatchProblem b;
  for (const auto& T : start_cam_from_world) b.poses.push_back(pose_vector_of(T));
  b.points = TrackPoints(start_points);
  BatchStart start{b.poses, b.points, {}};
  if (settings.known_distance_m != 0 && !b.poses.empty()) {
    start.known = known_distance_factor(b.poses, settings.known_distance_m);
    if (!start.known.problem.empty()) {
      result.message = "known_distance_m: " + start.known.problem;
      return result;
    }
  }
  if (const std::string wrong = camera_prior_problem(camera, settings.camera_prior);
      !wrong.empty()) {
    result.message = "camera_prior: " + wrong;
    return result;
  }

  const camera::CatadioptricCamera optimised = batch_camera(camera);
  const int threads = core::solver_threads(settings.threads, 2 * observations.size());
  const std::vector<char> ok = projectable(optimised, observations, b.poses, b.points, threads);
  std::vector<core::TrackObservation> used_observations;
  for (size_t i = 0; i < observations.size(); ++i)
    if (ok[i]) used_observations.push_back(observations[i]);
  const bool refine_camera = !settings.camera_prior.empty();
  b.camera_block = optimised.params();
  ceres::Problem::Options problem_options;
  if (refine_camera) {
    b.shared = std::make_unique<camera::SharedCamera>(optimised, b.camera_block.data());
    problem_options.evaluation_callback = b.shared.get();
  }
  b.problem = std::make_unique<ceres::Problem>(problem_options);
  ceres::Problem& problem = *b.problem;
  // With the sensors' terms, they weigh the pixels by this.
  const double pixel_weight = extra ? 1 / (settings.pixel_sigma * settings.pixel_sigma) : 0;
  b.projections = add_projections(optimised, used_observations, settings, extra != nullptr,
                                  &b.poses, &b.points, &b.inverse_scale, b.shared.get(),
                                  b.camera_block.data(), &problem);
  const double used = static_cast<double>(used_observations.size());
  if (used == 0 || b.poses.empty()) {
    result.message = "no observation can be projected from the starting estimate";
    return result;
  }
  problem.SetParameterBlockConstant(&b.inverse_scale);
  if (refine_camera) {
    add_camera_block(optimised, settings, b.camera_block.data(), &problem);
    // The camera is held while the scale is decided: the mirror's size along its axis trades
    // against the scene's scale, and freed it would leave the scale to the prior alone.
    problem.SetParameterBlockConstant(b.camera_block.data());
  }
  const bool gauge_fixed = extra && extra->add(&problem, &b.poses);
  if (!gauge_fixed && problem.HasParameterBlock(b.poses[0].data()))
    problem.SetParameterBlockConstant(b.poses[0].data());

  const double dof =
      degrees_of_freedom(problem, gauge_fixed, refine_camera ? optimised.num_params() : 0);
  b.options = batch_solver_options(&problem, &b.points, &b.poses, used_observations,
                                   static_cast<int>(b.poses.size()), settings, threads, dof);
  // With extra residuals or the camera's prior, the pixel figures are the reprojections' alone.
  const double initial_reprojection_cost = extra ? b.reprojection_cost(pixel_weight) : 0;
  // With the motion sensors' terms that fix the scale (odometry, GPS) the solve is the plain one.
  const bool scale_from_images = !extra || !extra->fixes_scale();
  // Whether any camera moves from the first in the start: else there is no scale to speak of.
  const bool moves = scale_gauge(problem, &b.poses).pose != nullptr;
  ScaleSolve scaled;
  if (scale_from_images && settings.scale_start && problem.HasParameterBlock(b.poses[0].data())) {
    scaled = solve_with_scale(&problem, b.options, &b.poses, &b.points, &b.inverse_scale,
                              &b.summary);
    if (scaled.solved) b.count(b.summary);
  }
  // Else the plain problem, from the scaled estimate when it moved (it is lower in cost).
  if (!scaled.converged) b.solve();
  double variance_dof = dof;
  if (scale_from_images)
    variance_dof = decide_scale(&b, start, settings, extra != nullptr, moves, dof, &result);
  else
    result.scale_source = BatchScale::kFromSensors;
  if (refine_camera)
    refine_camera_where_scale_known(&b, optimised, settings.camera_prior, extra != nullptr,
                                    variance_dof, &result);

  take_solution(b, extra ? initial_reprojection_cost : b.initial_cost, pixel_weight, used,
                variance_dof, &result);
  if (settings.covariances && b.summary.IsSolutionUsable())
    compute_covariances(&problem, b.poses, b.points, used_observations, settings, extra,
                        result.camera_refined ? b.camera_block.data() : nullptr, threads, &result);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

ceres::CostFunction* make_projection_cost(const camera::CatadioptricCamera* camera,
                                          const Eigen::Vector2d& pixel) {
  return new ProjectionCost(camera, pixel);
}

}  // namespace omnisfm::sfm
