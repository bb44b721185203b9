// A fixed-lag smoother over the drive, vision alone (not a benchmark: one run, a line per window).
// The batch's problem (its residual, poses and points, no motion or depth priors) solved window by
// window: each window of WINDOW frames starts from the online filter's estimate, and once solved
// its first STEP frames leave it for good. What their measurements said of the points the next
// window still sees goes on to it as a Gaussian prior on those points: the Schur complement of
// the leaving frames' normal equations at the solution, with its gradient. So each window takes
// what came before with its uncertainty, where holding the frames two windows share took their
// errors as exact. Memory is bounded by the window; the lag is STEP to WINDOW frames.
//   drive_fixed_lag [frames=20000] [seed=1] [noise=0.2] [window=2000] [step=1600]
//   [iterations=50] [tolerance=1e-6] [first_scale=0] [filter_window=0] [first_window=0]
// iterations and tolerance: each window's Levenberg-Marquardt (tolerance Ceres' function
// tolerance). first_scale 1 starts at the scale that makes the filter's drive as long as the
// truth's, 2 at the one that makes its first window's so (studies of what the scale does: the
// images fix a window's scale only loosely, and the solves keep the one they start from).
// first_window, longer than WINDOW: the first window that long, solved first by the batch with its
// scale free (the images' scale over it, however loosely they fix it), the next starting
// WINDOW - STEP frames before its end. filter_window: the filter's smoothing_window_frames.
// At the end, the mean rotation error after a similarity alignment, as drive_nees prints it;
// 20,000 frames take 3-4 minutes.

#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "omnisfm/core/pose_vector.h"
#include "omnisfm/eval/filter_run.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sim/endless_drive.h"
#include "setting_assignment.h"

namespace {

using namespace omnisfm;

// The prior a window's leaving frames leave on the points the next window still sees:
// r = sqrt_information (x - mean) + offset, x the points stacked.
class PointsPrior : public ceres::CostFunction {
 public:
  PointsPrior(Eigen::MatrixXd sqrt_information, Eigen::VectorXd mean, Eigen::VectorXd offset)
      : sqrt_information_(std::move(sqrt_information)),
        mean_(std::move(mean)),
        offset_(std::move(offset)) {
    set_num_residuals(static_cast<int>(mean_.size()));
    for (Eigen::Index k = 0; k < mean_.size() / 3; ++k)
      mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const Eigen::Index n = mean_.size();
    Eigen::VectorXd x(n);
    for (Eigen::Index k = 0; k < n / 3; ++k)
      x.segment<3>(3 * k) = Eigen::Map<const Eigen::Vector3d>(parameters[k]);
    Eigen::Map<Eigen::VectorXd>(residuals, n) = sqrt_information_ * (x - mean_) + offset_;
    if (jacobians)
      for (Eigen::Index k = 0; k < n / 3; ++k)
        if (jacobians[k])
          Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
              jacobians[k], n, 3) = sqrt_information_.middleCols<3>(3 * k);
    return true;
  }

 private:
  Eigen::MatrixXd sqrt_information_;
  Eigen::VectorXd mean_, offset_;
};

struct Prior {
  std::vector<int> tracks;
  Eigen::MatrixXd sqrt_information;
  Eigen::VectorXd mean, offset;
};

}  // namespace

int main(int argc, char** argv) {
  sfm::use_one_blas_thread();
  double frames_value = 20000, seed_value = 1, noise = 0.2, window_value = 2000, step_value = 1600,
         iterations_value = 50, first_scale = 0, filter_window = 0, first_window_value = 0,
         tolerance = 1e-6;
  const bench::Setters settable = {
      {"frames", [&](double v) { frames_value = v; }},
      {"seed", [&](double v) { seed_value = v; }},
      {"noise", [&](double v) { noise = v; }},
      {"window", [&](double v) { window_value = v; }},
      {"step", [&](double v) { step_value = v; }},
      {"iterations", [&](double v) { iterations_value = v; }},
      {"first_scale", [&](double v) { first_scale = v; }},
      {"filter_window", [&](double v) { filter_window = v; }},
      {"first_window", [&](double v) { first_window_value = v; }},
      {"tolerance", [&](double v) { tolerance = v; }},
  };
  for (int k = 1; k < argc; ++k)
    if (!bench::apply_assignment(argv[k], settable)) {
      std::fprintf(stderr, "drive_fixed_lag: unknown setting, or not a number: %s\n", argv[k]);
      return 2;
    }
  // Whole numbers within their types' ranges, as drive_truth_batch takes them.
  const auto whole = [](double v) { return v == std::floor(v) && v >= 0 && v <= 1e8; };
  if (!whole(frames_value) || !whole(seed_value) || !whole(window_value) || !whole(step_value) ||
      !whole(iterations_value) || !whole(first_window_value) || !whole(filter_window)) {
    std::fprintf(stderr,
                 "drive_fixed_lag: frames, seed, window, step, iterations, first_window and "
                 "filter_window are whole numbers of 0 or more\n");
    return 2;
  }
  const int frames = static_cast<int>(frames_value);
  const int window = static_cast<int>(window_value);
  const int step = static_cast<int>(step_value);
  const int first_window = std::max(window, static_cast<int>(first_window_value));
  // Three frames or more shared by consecutive windows: the next window's start is brought onto
  // the last by them.
  if (frames < 8 || step < 1 || window - step < 3) {
    std::fprintf(stderr, "drive_fixed_lag: at least 8 frames, and 0 < step <= window - 3\n");
    return 2;
  }
  const sim::Dataset d = sim::long_drive(frames, noise, static_cast<std::uint64_t>(seed_value));

  // The filter's estimate, in its own frame (the first camera's) and scale.
  sfm::FilterSettings filter_settings;
  filter_settings.smoothing_window_frames = static_cast<int>(filter_window);
  sfm::OnlineFilter filter(d.camera, filter_settings);
  std::map<int, Eigen::Vector3d> filter_points;
  filter.on_point_ended([&](int track, const Eigen::Vector3d& p) { filter_points[track] = p; });
  std::vector<Eigen::Isometry3d> filter_world_from_cam;
  eval::run_filter(d, nullptr, filter_settings, &filter, [&](int) {
    filter_world_from_cam.push_back(filter.cam_from_world().inverse());
  });
  for (const auto& [track, p] : filter.points()) filter_points[track] = p;
  {
    const eval::TrajectoryErrors e =
        eval::trajectory_errors(filter_world_from_cam, d.world_from_cam, true);
    std::printf("# the filter: %.2f %% after a similarity, mean rotation error %.2f deg\n",
                e.translation_error_percent, e.mean_rotation_error_deg);
  }

  std::vector<std::vector<core::TrackPixel>> seen(frames);
  std::map<int, int> last_seen;  // track -> the last frame that sees it
  for (const core::TrackObservation& o : d.observations)
    if (filter_points.count(o.track)) {
      seen[o.frame].push_back({o.track, o.pixel});
      last_seen[o.track] = std::max(last_seen[o.track], o.frame);
    }

  // The estimate: poses (cam_from_world) and points, the solved ones and the rest brought onto
  // them from the filter's.
  std::vector<core::PoseVector> pose(frames);
  std::map<int, Eigen::Vector3d> point;
  std::set<int> solved_tracks;
  const auto bring_filter = [&](double s, const Eigen::Matrix3d& Rs, const Eigen::Vector3d& ts,
                                int from_frame) {
    for (int f = from_frame; f < frames; ++f) {
      Eigen::Isometry3d w = Eigen::Isometry3d::Identity();
      w.linear() = Rs * filter_world_from_cam[f].linear();
      w.translation() = s * Rs * filter_world_from_cam[f].translation() + ts;
      pose[f] = core::pose_vector_of(w.inverse());
    }
    for (const auto& [track, p] : filter_points)
      if (!solved_tracks.count(track)) point[track] = s * Rs * p + ts;
  };
  double start_scale = 1;
  if (first_scale != 0) {
    // 1: the drive's length right; 2: the first window's.
    const int end = first_scale == 2 ? std::min(window, frames) - 1 : frames - 1;
    start_scale =
        (d.world_from_cam[end].translation() - d.world_from_cam[0].translation()).norm() /
        (filter_world_from_cam[end].translation() - filter_world_from_cam[0].translation()).norm();
  }
  bring_filter(start_scale, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 0);

  const camera::CatadioptricCamera camera = sfm::batch_camera(d.camera);
  Prior prior;
  double seconds = 0;
  for (int a = 0; a < frames;) {
    const int first = a;
    const auto started = std::chrono::steady_clock::now();
    // The first window may be longer: the batch, its scale free, solves it first.
    const int length = a == 0 ? first_window : window;
    const int leave = length - (window - step);
    const int b = std::min(a + length, frames);
    if (a == 0 && first_window > window) {
      std::vector<core::TrackObservation> observations;
      std::map<int, Eigen::Vector3d> start_points;
      std::vector<Eigen::Isometry3d> start(b);
      for (int f = 0; f < b; ++f) {
        start[f] = core::isometry_of(pose[f]).inverse();
        for (const core::TrackPixel& o : seen[f]) {
          observations.push_back({f, o.track, o.pixel});
          start_points[o.track] = point[o.track];
        }
      }
      sfm::BatchSettings batch;
      batch.covariances = false;
      batch.max_free_scale_sigma = INFINITY;
      batch.pixel_sigma = noise > 0 ? noise : 0.2;
      batch.threads = 1;
      batch.max_iterations = static_cast<int>(iterations_value);
      const sfm::BatchResult r =
          sfm::batch_adjust(d.camera, observations, start, start_points, batch);
      if (!r.usable()) {
        std::fprintf(stderr, "drive_fixed_lag: the first window's batch failed: %s\n",
                     r.message.c_str());
        return 1;
      }
      for (int f = 0; f < b; ++f) pose[f] = r.cam_from_world_parameters[f];
      for (const auto& [track, p] : r.points) point[track] = p;
      std::printf("# the first window's batch: %d iterations, the images' scale sigma %.3f\n",
                  r.iterations, r.scale_sigma_relative);
    }
    const bool last = b == frames;
    ceres::Problem problem;
    std::vector<ceres::ResidualBlockId> leaving, pixels;
    for (int f = a; f < b; ++f)
      for (const core::TrackPixel& o : seen[f]) {
        // As the batch does, an observation its start cannot project is left out.
        ceres::CostFunction* cost = sfm::make_projection_cost(&camera, o.pixel);
        const double* at[] = {pose[f].data(), point[o.track].data()};
        double residual[2];
        if (!cost->Evaluate(at, residual, nullptr)) {
          delete cost;
          continue;
        }
        const ceres::ResidualBlockId id =
            problem.AddResidualBlock(cost, nullptr, pose[f].data(), point[o.track].data());
        pixels.push_back(id);
        if (f < a + leave) leaving.push_back(id);
      }
    if (a == 0 && problem.HasParameterBlock(pose[0].data()))
      problem.SetParameterBlockConstant(pose[0].data());
    if (!prior.tracks.empty()) {
      std::vector<double*> blocks;
      for (const int track : prior.tracks) blocks.push_back(point[track].data());
      leaving.push_back(problem.AddResidualBlock(
          new PointsPrior(prior.sqrt_information, prior.mean, prior.offset), nullptr, blocks));
    }
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    std::vector<double*> blocks;
    problem.GetParameterBlocks(&blocks);
    // The prior ties its points together: they join the poses in the reduced system.
    std::set<const double*> in_prior;
    for (const int track : prior.tracks) in_prior.insert(point[track].data());
    for (double* block : blocks)
      ordering->AddElementToGroup(
          block, problem.ParameterBlockSize(block) == 3 && !in_prior.count(block) ? 0 : 1);
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_SCHUR;
    options.linear_solver_ordering = ordering;
    options.max_num_iterations = static_cast<int>(iterations_value);
    options.num_threads = 1;
    options.function_tolerance = tolerance;
    options.parameter_tolerance = tolerance * 1e-2;
    options.gradient_tolerance = tolerance * 1e-4;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (!summary.IsSolutionUsable()) {
      std::fprintf(stderr, "drive_fixed_lag: the window from %d: %s\n", a, summary.message.c_str());
      return 1;
    }
    for (int f = a; f < b; ++f)
      for (const core::TrackPixel& o : seen[f]) solved_tracks.insert(o.track);
    solved_tracks.insert(prior.tracks.begin(), prior.tracks.end());
    ceres::Problem::EvaluateOptions of_pixels;
    of_pixels.residual_blocks = pixels;
    double pixel_cost = 0;
    problem.Evaluate(of_pixels, &pixel_cost, nullptr, nullptr, nullptr);
    const double rms_px = std::sqrt(pixel_cost / std::max<size_t>(1, pixels.size()));

    if (!last) {
      // The leaving frames' residuals (and the prior they carried) at the solution: the points
      // they touch that frames after them see stay, the rest (their poses, points seen only by
      // them) are marginalised.
      const int next = a + leave;
      std::set<int> touched;
      for (int f = a; f < next; ++f)
        for (const core::TrackPixel& o : seen[f]) touched.insert(o.track);
      for (const int track : prior.tracks) touched.insert(track);
      std::vector<int> kept;
      std::vector<double*> marginal_blocks, kept_blocks;
      for (const int track : touched)
        if (last_seen[track] >= next) {
          kept.push_back(track);
          kept_blocks.push_back(point[track].data());
        } else {
          marginal_blocks.push_back(point[track].data());
        }
      for (int f = a; f < next; ++f)
        if (problem.HasParameterBlock(pose[f].data()) &&
            !problem.IsParameterBlockConstant(pose[f].data()))
          marginal_blocks.push_back(pose[f].data());
      int nm = 0;
      for (double* block : marginal_blocks) nm += problem.ParameterBlockSize(block);
      const int nk = 3 * static_cast<int>(kept.size());
      ceres::Problem::EvaluateOptions evaluate;
      evaluate.parameter_blocks = marginal_blocks;
      evaluate.parameter_blocks.insert(evaluate.parameter_blocks.end(), kept_blocks.begin(),
                                       kept_blocks.end());
      evaluate.residual_blocks = leaving;
      std::vector<double> residuals;
      ceres::CRSMatrix crs;
      if (!problem.Evaluate(evaluate, nullptr, &residuals, nullptr, &crs) ||
          crs.num_cols != nm + nk) {
        std::fprintf(stderr, "drive_fixed_lag: the leaving frames could not be evaluated\n");
        return 1;
      }
      const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> J(
          crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()), crs.rows.data(),
          crs.cols.data(), crs.values.data());
      const Eigen::Map<const Eigen::VectorXd> r(residuals.data(),
                                                static_cast<Eigen::Index>(residuals.size()));
      const Eigen::SparseMatrix<double> H = J.transpose() * J;
      const Eigen::VectorXd g = J.transpose() * r;
      Eigen::SparseMatrix<double> Hmm = H.topLeftCorner(nm, nm);
      // A little damping: a point the leaving frames barely parallax is nearly free in depth.
      for (int k = 0; k < nm; ++k) Hmm.coeffRef(k, k) += 1e-9 * (1 + Hmm.coeff(k, k));
      const Eigen::MatrixXd Hmk = Eigen::MatrixXd(H.topRightCorner(nm, nk));
      const Eigen::MatrixXd Hkk = Eigen::MatrixXd(H.bottomRightCorner(nk, nk));
      Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> llt(Hmm);
      if (llt.info() != Eigen::Success) {
        std::fprintf(stderr, "drive_fixed_lag: the leaving frames' system is singular\n");
        return 1;
      }
      const Eigen::MatrixXd X = llt.solve(Hmk);
      const Eigen::VectorXd y = llt.solve(g.head(nm));
      Eigen::MatrixXd S = Hkk - Hmk.transpose() * X;
      S = 0.5 * (S + S.transpose()).eval();
      const Eigen::VectorXd gk = g.tail(nk) - Hmk.transpose() * y;
      // Its square root through the eigenvalues: the points' information may be nearly singular
      // along the scale.
      if (kept.empty()) {
        std::fprintf(stderr, "drive_fixed_lag: no point joins the window from %d to the next\n", a);
        return 1;
      }
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(S);
      const Eigen::VectorXd lambda =
          eig.eigenvalues().cwiseMax(1e-12 * eig.eigenvalues().maxCoeff());
      prior.tracks = kept;
      prior.sqrt_information = lambda.cwiseSqrt().asDiagonal() * eig.eigenvectors().transpose();
      prior.offset =
          lambda.cwiseSqrt().cwiseInverse().asDiagonal() * (eig.eigenvectors().transpose() * gk);
      prior.mean.resize(nk);
      for (size_t k = 0; k < kept.size(); ++k) prior.mean.segment<3>(3 * k) = point[kept[k]];

      // The frames not yet solved from the filter's, onto this window's last frame: its
      // orientation and position, and the path's length over the frames the next window shares
      // (a fit of the positions alone leaves the roll free on a straight stretch).
      const Eigen::Isometry3d solved_last = core::isometry_of(pose[b - 1]).inverse();
      double solved_length = 0, filter_length = 0;
      for (int f = next + 1; f < b; ++f) {
        solved_length += (core::isometry_of(pose[f]).inverse().translation() -
                          core::isometry_of(pose[f - 1]).inverse().translation())
                             .norm();
        filter_length +=
            (filter_world_from_cam[f].translation() - filter_world_from_cam[f - 1].translation())
                .norm();
      }
      const double s = filter_length > 0 ? solved_length / filter_length : 1;
      const Eigen::Matrix3d Rs =
          solved_last.linear() * filter_world_from_cam[b - 1].linear().transpose();
      bring_filter(s, Rs,
                   solved_last.translation() - s * Rs * filter_world_from_cam[b - 1].translation(),
                   b);
      a = next;
    } else {
      a = frames;
    }
    const double took =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    seconds += took;
    // The window's scale against the truth's: a similarity from the true camera positions to its.
    Eigen::Matrix3Xd estimated(3, b - first), true_positions(3, b - first);
    for (int f = first; f < b; ++f) {
      estimated.col(f - first) = core::isometry_of(pose[f]).inverse().translation();
      true_positions.col(f - first) = d.world_from_cam[f].translation();
    }
    const double scale = std::cbrt(
        Eigen::umeyama(true_positions, estimated, true).topLeftCorner<3, 3>().determinant());
    std::printf(
        "# window %d-%d: %d iterations, %.4f px, its scale %.3f of the truth's, %zu points "
        "carried on, %.1f s\n",
        first, b, static_cast<int>(summary.iterations.size()) - 1, rms_px, scale,
        prior.tracks.size(), took);
    std::fflush(stdout);
  }
  std::vector<Eigen::Isometry3d> estimate;
  for (const core::PoseVector& p : pose) estimate.push_back(core::isometry_of(p).inverse());
  const eval::TrajectoryErrors e = eval::trajectory_errors(estimate, d.world_from_cam, true);
  std::printf("# after a similarity %.2f %% of %.0f m, mean rotation error %.2f deg, %.0f s\n",
              e.translation_error_percent, e.distance_travelled_m, e.mean_rotation_error_deg,
              seconds);
}
