// Speed of the estimators: the online filter per frame at several numbers of points and over the
// simulated rover sequence, the batch adjustment on the simulated rover and on long sequences (up
// to 2,000 images), with analytic Jacobians and, as the peer, Ceres' numeric differentiation of
// the same model; and the rover pipeline with and without the motion sensors.

#include <benchmark/benchmark.h>
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <sys/resource.h>

#include <map>
#include <tuple>

#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/sim/trajectories.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/sfm/blas_threads.h"

namespace {

using namespace omnisfm;

// The rover's rig and motion with `count` points spread around its path, all tracked throughout.
struct FilterInput {
  camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  std::vector<std::vector<sfm::TrackPixel>> frames;
};

FilterInput rover_frames(int count) {
  FilterInput input;
  const sim::Dataset d{"rover", input.camera, {}, sim::rover_trajectory(0.6), {}, {}, {}, {}, {}, {}};
  std::mt19937_64 rng(7);
  input.frames = sfm::observations_by_frame(sim::steady_ground_tracks(d, count, 0.2, rng));
  return input;
}

// Time per frame of the filter over 20 frames from `first`, every point in the state from
// frame 0, with the default settings or with `update_iterations` changed. The frames before
// `first` run untimed. The smoothed start (after frame 19) runs only in the frames 40-59 case,
// before the timing.
void filter_frames(benchmark::State& state, int update_iterations, int first) {
  const FilterInput input = rover_frames(static_cast<int>(state.range(0)));
  sfm::FilterSettings settings;
  if (update_iterations > 0) settings.update_iterations = update_iterations;
  if (first < settings.smoothed_start_frames) settings.smoothed_start_frames = 0;
  for (auto _ : state) {
    state.PauseTiming();
    sfm::OnlineFilter filter(input.camera, settings);
    for (int f = 0; f < first; ++f) filter.process_frame(f, input.frames[f]);
    state.ResumeTiming();
    for (int f = first; f < first + 20; ++f) filter.process_frame(f, input.frames[f]);
  }
  state.counters["s_per_frame"] = benchmark::Counter(
      20.0 * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Frames 1-20: every point is new, its depth known only to the prior; the hardest updates.
void BM_FilterFrame(benchmark::State& state) { filter_frames(state, 0, 1); }
BENCHMARK(BM_FilterFrame)->Arg(30)->Arg(60)->Arg(112)->Arg(200)->Unit(benchmark::kMillisecond);

// Frames 40-59: the points' depths have settled, as for most frames of a long sequence.
void BM_FilterFrameSettled(benchmark::State& state) { filter_frames(state, 0, 40); }
BENCHMARK(BM_FilterFrameSettled)->Arg(30)->Arg(60)->Arg(112)->Arg(200)
    ->Unit(benchmark::kMillisecond);

// The 20th frame with the smoothed start that ends it: the update and the exact solution of the
// first 20 frames' poses and points, once per sequence.
void BM_FilterSmoothedStart(benchmark::State& state) {
  const FilterInput input = rover_frames(static_cast<int>(state.range(0)));
  sfm::FilterSettings settings;
  for (auto _ : state) {
    state.PauseTiming();
    sfm::OnlineFilter filter(input.camera, settings);
    for (int f = 0; f + 1 < settings.smoothed_start_frames; ++f)
      filter.process_frame(f, input.frames[f]);
    state.ResumeTiming();
    filter.process_frame(settings.smoothed_start_frames - 1,
                         input.frames[settings.smoothed_start_frames - 1]);
    benchmark::DoNotOptimize(filter.smoothed_start().size());
  }
}
BENCHMARK(BM_FilterSmoothedStart)->Arg(30)->Arg(112)->Unit(benchmark::kMillisecond);

// The classic EKF: one linearisation per frame instead of the iterated update.
void BM_FilterFrameOneIteration(benchmark::State& state) { filter_frames(state, 1, 1); }
BENCHMARK(BM_FilterFrameOneIteration)->Arg(30)->Arg(60)->Arg(112)->Arg(200)
    ->Unit(benchmark::kMillisecond);

// The filter over the whole simulated rover sequence (seed 1): tracks that end and start, the
// seven mistracked ones rejected, the smoothed start included; per frame.
void BM_FilterRoverSequence(benchmark::State& state) {
  sim::SimulationOptions options;
  options.scenario = "rover";
  const sim::Dataset d = sim::simulate(options);
  const auto frames = sfm::observations_by_frame(d.observations);
  long linearisations = 0;
  for (auto _ : state) {
    sfm::OnlineFilter filter(d.camera, sfm::FilterSettings{});
    for (size_t f = 0; f < frames.size(); ++f)
      filter.process_frame(static_cast<int>(f), frames[f]);
    linearisations = filter.linearisations();
  }
  const double n = static_cast<double>(frames.size());
  state.counters["s_per_frame"] = benchmark::Counter(
      n * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["linearisations_per_frame"] = static_cast<double>(linearisations) / n;
}
BENCHMARK(BM_FilterRoverSequence)->Unit(benchmark::kMillisecond);

struct BatchInput {
  camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  std::vector<core::TrackObservation> tracks;
  sfm::SfmResult start;
};

const BatchInput& rover_batch() {
  static const BatchInput input = [] {
    BatchInput b;
    sim::SimulationOptions options;
    options.scenario = "rover";
    const sim::Dataset d = sim::simulate(options);
    b.camera = d.camera;
    for (const auto& o : d.observations) b.tracks.push_back({o.frame, o.track, o.pixel});
    sfm::SfmSettings settings;
    settings.run_batch = false;
    b.start = sfm::run_sfm(d.camera, b.tracks, settings);
    return b;
  }();
  return input;
}

void BM_BatchRover(benchmark::State& state) {
  const BatchInput& b = rover_batch();
  sfm::BatchSettings settings;
  settings.covariances = false;
  int iterations = 0;
  double solve_seconds = 0;
  for (auto _ : state) {
    const auto result = sfm::batch_adjust(b.camera, b.tracks, b.start.online_world_from_cam,
                                          b.start.online_points, settings);
    iterations = result.iterations;
    solve_seconds += result.solve_seconds;
  }
  state.counters["lm_iterations"] = iterations;
  // Ceres' solves alone, without building the problem and checking the start.
  state.counters["solve_ms"] =
      benchmark::Counter(1e3 * solve_seconds, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_BatchRover)->Unit(benchmark::kMillisecond);

// The whole rover pipeline (filter, then batch): 0 vision alone, 1 fused with the wheel odometry
// and the gyro, 2 with GPS too; what the motion sensors' propagation and terms cost.
void BM_FusedRover(benchmark::State& state) {
  static const auto inputs = [] {
    sim::SimulationOptions options;
    options.scenario = "rover";
    const sim::Dataset d = sim::simulate(options);
    const sim::DeadReckoningOptions dead_reckoning_options;
    const sim::DeadReckoning dead_reckoning =
        sim::simulate_dead_reckoning(d, dead_reckoning_options);
    const sim::GpsTrack gps = sim::simulate_gps(d, sim::GpsOptions());
    return std::make_tuple(
        d, eval::motion_sensors(&dead_reckoning, dead_reckoning_options, nullptr),
        eval::motion_sensors(&dead_reckoning, dead_reckoning_options, &gps));
  }();
  const auto& [d, odometry_and_gyro, with_gps] = inputs;
  const sfm::MotionSensors none;
  const sfm::MotionSensors* sensors[] = {&none, &odometry_and_gyro, &with_gps};
  sfm::SfmSettings settings;
  settings.batch.covariances = false;
  int iterations = 0;
  double batch_seconds = 0;
  for (auto _ : state) {
    const auto result = sfm::run_fused_sfm(d.camera, d.observations, d.timestamps,
                                           *sensors[state.range(0)], settings);
    iterations = result.batch.iterations;
    batch_seconds += result.batch.seconds;
  }
  state.counters["lm_iterations"] = iterations;
  state.counters["batch_ms"] =
      benchmark::Counter(1e3 * batch_seconds, benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_FusedRover)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

// A long drive for the batch's scaling (sim::long_drive, 0.2 px noise), started from the truth
// with centimetre errors, as a filter would give.
struct ScaledProblem {
  sim::Dataset drive;
  std::vector<Eigen::Isometry3d> start_world_from_cam;
  std::map<int, Eigen::Vector3d> start_points;
};

ScaledProblem scaled_problem(int images) {
  ScaledProblem problem{sim::long_drive(images, 0.2, 11), {}, {}};
  std::mt19937_64 rng(12);
  const auto normal3 = [&rng] {
    return Eigen::Vector3d(sim::standard_normal(rng), sim::standard_normal(rng),
                           sim::standard_normal(rng));
  };
  for (size_t track = 0; track < problem.drive.track_points.size(); ++track)
    problem.start_points[static_cast<int>(track)] =
        problem.drive.track_points[track] + 0.03 * normal3();
  for (int f = 0; f < images; ++f) {
    Eigen::Isometry3d T = problem.drive.world_from_cam[f];
    if (f > 0) {
      const Eigen::Vector3d w = 0.005 * normal3();
      T.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() * T.linear();
      T.translation() += 0.01 * normal3();
    }
    problem.start_world_from_cam.push_back(T);
  }
  return problem;
}

// The batch to convergence on a long drive of state.range(0) images; the process's peak
// resident memory so far is reported with it.
void BM_BatchScaled(benchmark::State& state) {
  const ScaledProblem problem = scaled_problem(static_cast<int>(state.range(0)));
  sfm::BatchSettings settings;
  settings.covariances = false;
  sfm::BatchResult result;
  for (auto _ : state)
    result = sfm::batch_adjust(problem.drive.camera, problem.drive.observations,
                               problem.start_world_from_cam, problem.start_points, settings);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["lm_iterations"] = result.iterations;
  state.counters["observations"] = static_cast<double>(problem.drive.observations.size());
  state.counters["converged"] = result.converged;
  state.counters["final_rms_px"] = result.final_rms_px;
  // The scale: its relative standard deviation, and whether the batch held it (1) or not (0).
  state.counters["scale_sigma_percent"] = 100 * result.scale_sigma_relative;
  state.counters["scale_held"] = result.scale_source != sfm::BatchScale::kFromImages;
  state.counters["peak_rss_MB"] = usage.ru_maxrss / 1024.0;
}
BENCHMARK(BM_BatchScaled)->Arg(250)->Arg(500)->Arg(1000)->Arg(2000)->Iterations(1)
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// The peer: the same residual, differentiated numerically by Ceres.
struct NumericProjection {
  const camera::CatadioptricCamera* camera;
  Eigen::Vector2d pixel;
  bool operator()(const double* pose, const double* point, double* residual) const {
    double rotated[3];
    ceres::AngleAxisRotatePoint(pose, point, rotated);
    Eigen::Vector2d q;
    if (!camera->project({rotated[0] + pose[3], rotated[1] + pose[4], rotated[2] + pose[5]}, &q))
      return false;
    residual[0] = q.x() - pixel.x();
    residual[1] = q.y() - pixel.y();
    return true;
  }
};

// The rover problem from the filter's start: poses as (angle-axis, translation), every residual
// analytic or numeric; points are put in group 0 of `ordering` (eliminated) and poses in group 1.
struct RoverProblem {
  std::vector<Eigen::Matrix<double, 6, 1>> poses;
  std::map<int, Eigen::Vector3d> points;
  ceres::Problem problem;
  std::shared_ptr<ceres::ParameterBlockOrdering> ordering =
      std::make_shared<ceres::ParameterBlockOrdering>();

  RoverProblem(const BatchInput& b, bool numeric) : points(b.start.online_points) {
    // The batch's parameters: cam_from_world.
    for (const auto& T : b.start.online_world_from_cam)
      poses.push_back(omnisfm::core::pose_vector_of(T.inverse()));
    for (const auto& o : b.tracks) {
      auto p = points.find(o.track);
      if (p == points.end()) continue;
      ceres::CostFunction* cost =
          numeric ? static_cast<ceres::CostFunction*>(
                        new ceres::NumericDiffCostFunction<NumericProjection, ceres::CENTRAL, 2,
                                                           6, 3>(
                            new NumericProjection{&b.camera, o.pixel}))
                  : sfm::make_projection_cost(&b.camera, o.pixel);
      problem.AddResidualBlock(cost, nullptr, poses[o.frame].data(), p->second.data());
      ordering->AddElementToGroup(p->second.data(), 0);
      ordering->AddElementToGroup(poses[o.frame].data(), 1);
    }
  }
};

// One linearisation of the whole rover problem (every residual and Jacobian), analytic or
// numeric: the per-iteration cost that differs between the two.
void BM_RoverJacobians(benchmark::State& state) {
  const bool numeric = state.range(0) == 1;
  RoverProblem rover(rover_batch(), numeric);
  ceres::Problem& problem = rover.problem;
  double cost = 0;
  std::vector<double> residuals;
  ceres::CRSMatrix jacobian;
  for (auto _ : state) {
    problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, &residuals, nullptr, &jacobian);
    benchmark::DoNotOptimize(cost);
  }
  state.SetLabel(numeric ? "numeric (central differences)" : "analytic");
}
BENCHMARK(BM_RoverJacobians)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Whole Levenberg-Marquardt iterations of the plain rover problem (the first pose held, points
// eliminated, conjugate gradients on the reduced system as the batch runs it, 2 threads), analytic
// or numeric: what differentiating numerically costs per iteration once the linear solve, which
// both share, is counted. Counter: wall seconds per iteration.
void BM_RoverIterations(benchmark::State& state) {
  constexpr int kIterations = 4;
  const bool numeric = state.range(0) == 1;
  const BatchInput& b = rover_batch();
  int iterations = 0;
  double seconds = 0;
  for (auto _ : state) {
    state.PauseTiming();
    RoverProblem rover(b, numeric);
    ceres::Problem& problem = rover.problem;
    problem.SetParameterBlockConstant(rover.poses[0].data());
    ceres::Solver::Options options;
    options.linear_solver_ordering = rover.ordering;
    options.linear_solver_type = ceres::ITERATIVE_SCHUR;
    options.preconditioner_type = ceres::SCHUR_JACOBI;
    options.eta = 1e-6;
    options.initial_trust_region_radius = 1e7;
    options.max_num_iterations = kIterations;
    options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 0;
    options.num_threads = 2;
    state.ResumeTiming();
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    iterations += static_cast<int>(summary.iterations.size()) - 1;
    seconds += summary.minimizer_time_in_seconds;
  }
  state.counters["s_per_iteration"] = seconds / std::max(1, iterations);
  state.SetLabel(numeric ? "numeric (central differences)" : "analytic");
}
BENCHMARK(BM_RoverIterations)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  omnisfm::sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
