#pragma once
// The pipeline's batch scale on the simulated experiments against the truth, and the checks made
// over seeds: every batch within a factor 2 of the true scale or held, and the reported standard
// deviations of the free ones honest.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {

struct ScaleRun {
  std::string scenario;
  std::uint64_t seed = 0;
  BatchScale source = BatchScale::kNoTranslation;
  double sigma = NAN;         // BatchResult::scale_sigma_relative
  double scale = NAN;         // the batch's length per true length, after a similarity alignment
  double filter_scale = NAN;  // the same of the filter's
  // The relative error of the inverse scale, in which the reported sigma is (nearly) Gaussian.
  double inverse_scale_error() const { return 1 / scale - 1; }
  double error_in_sigmas() const { return inverse_scale_error() / sigma; }
  std::string name() const { return scenario + " seed " + std::to_string(seed); }
};

inline double length_per_true_length(const std::vector<Eigen::Isometry3d>& world_from_cam,
                                     const sim::Dataset& d) {
  return 1 / eval::trajectory_errors(world_from_cam, d.world_from_cam, true).alignment.scale;
}

inline ScaleRun scale_run(const std::string& scenario, std::uint64_t seed) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.seed = seed;
  const sim::Dataset d = sim::simulate(options);
  SfmSettings settings;
  settings.batch.covariances = false;
  const SfmResult r = run_sfm(d.camera, d.observations, settings);
  EXPECT_TRUE(r.batch.converged) << scenario << " seed " << seed << ": " << r.batch.message;
  ScaleRun run;
  run.scenario = scenario;
  run.seed = seed;
  run.source = r.batch.scale_source;
  run.sigma = r.batch.scale_sigma_relative;
  run.scale = length_per_true_length(r.batch.world_from_cam, d);
  run.filter_scale = length_per_true_length(r.online_world_from_cam, d);
  return run;
}

// Every batch's scale within a factor 2 of the truth, or held (at the filter's, which it then
// keeps to 2 %: the held coordinate fixes the scale, the rest of the shape still moves).
inline void expect_within_a_factor_two_or_held(const std::vector<ScaleRun>& runs) {
  for (const ScaleRun& run : runs) {
    if (run.source == BatchScale::kFromImages) {
      EXPECT_LT(std::max(run.scale, 1 / run.scale), 2) << run.name() << ", sigma " << run.sigma;
      EXPECT_LE(run.sigma, kMaxFreeScaleSigma) << run.name();
    } else {
      ASSERT_EQ(run.source, BatchScale::kHeldAtStart) << run.name();
      EXPECT_GT(run.sigma, kMaxFreeScaleSigma) << run.name();
      EXPECT_NEAR(run.scale / run.filter_scale, 1, 0.02) << run.name();
    }
  }
}

// The free scales' errors against their reported sigmas: beyond 3 sigma in at most one run in
// `beyond_3_one_in` (rounded down), and the spread of error / sigma (its RMS) within
// [min_rms, max_rms]. Returns the RMS.
inline double expect_honest_sigmas(const std::vector<ScaleRun>& runs, int min_free_runs,
                                   int beyond_3_one_in, double min_rms, double max_rms) {
  int free_runs = 0;
  double sum_squares = 0;
  std::string beyond_3;
  int beyond_3_runs = 0;
  for (const ScaleRun& run : runs) {
    if (run.source != BatchScale::kFromImages) continue;
    ++free_runs;
    const double z = run.error_in_sigmas();
    sum_squares += z * z;
    if (!(std::abs(z) < 3)) {
      ++beyond_3_runs;
      beyond_3 += " " + run.name() + " (" + std::to_string(z) + ")";
    }
  }
  EXPECT_GE(free_runs, min_free_runs);
  EXPECT_LE(beyond_3_runs, free_runs / beyond_3_one_in) << "beyond 3 sigma:" << beyond_3;
  if (free_runs == 0) return NAN;
  const double rms = std::sqrt(sum_squares / free_runs);
  EXPECT_GE(rms, min_rms) << free_runs << " free runs";
  EXPECT_LE(rms, max_rms) << free_runs << " free runs";
  return rms;
}

}  // namespace omnisfm::sfm
