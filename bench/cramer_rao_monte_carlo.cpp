// Monte Carlo against the Cramer-Rao bound: the simulated rover's noise-free tracks (outliers
// removed) with fresh Gaussian noise per trial, the batch adjustment started from the truth, and
// the RMS error of the camera positions against the bound's RMS, in the batch's gauge (the first
// pose fixed at the truth).
//   cramer_rao_monte_carlo [TRIALS=50] [NOISE_PX=0.2]

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <set>

#include "omnisfm/eval/similarity_alignment.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/cramer_rao.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/sfm/blas_threads.h"

int main(int argc, char** argv) {
  omnisfm::sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  using namespace omnisfm;
  const int trials = argc > 1 ? std::atoi(argv[1]) : 50;
  const double noise = argc > 2 ? std::atof(argv[2]) : 0.2;
  sim::SimulationOptions options;
  options.scenario = "rover";
  options.tracking_noise_px = 0;
  const sim::Dataset d = sim::simulate(options);
  std::set<int> outliers;
  for (const auto& o : d.outliers) outliers.insert(o.track);
  std::vector<core::TrackObservation> exact;
  for (const auto& o : d.observations)
    if (!outliers.count(o.track)) exact.push_back({o.frame, o.track, o.pixel});
  const std::vector<Eigen::Isometry3d>& truth = d.world_from_cam;
  std::map<int, Eigen::Vector3d> points;
  for (const auto& o : exact) points[o.track] = d.track_points[o.track];

  const sfm::PositionBound bound = sfm::camera_position_bound(d.camera, exact, truth, points, noise);

  std::mt19937_64 rng(12345);
  double error2 = 0, aligned2 = 0;
  int count = 0;
  sfm::BatchSettings settings;
  settings.covariances = false;
  for (int trial = 0; trial < trials; ++trial) {
    std::vector<core::TrackObservation> noisy = exact;
    for (auto& o : noisy)
      o.pixel += noise * Eigen::Vector2d(sim::standard_normal(rng), sim::standard_normal(rng));
    const auto result = sfm::batch_adjust(d.camera, noisy, truth, points, settings);
    std::vector<Eigen::Vector3d> estimated, true_centres;
    for (size_t f = 1; f < truth.size(); ++f) {
      estimated.push_back(result.world_from_cam[f].translation());
      true_centres.push_back(truth[f].translation());
      error2 += (estimated.back() - true_centres.back()).squaredNorm();
      ++count;
    }
    const eval::Similarity s = eval::align(estimated, true_centres);
    for (size_t i = 0; i < estimated.size(); ++i)
      aligned2 += (s.apply(estimated[i]) - true_centres[i]).squaredNorm();
    std::fprintf(stderr, "\rtrial %d/%d", trial + 1, trials);
  }
  const double error_rms = std::sqrt(error2 / count), aligned_rms = std::sqrt(aligned2 / count);
  std::printf("\nrover, %d trials, %.2f px noise, RMS camera position error against the "
              "Cramer-Rao bound:\n"
              "  first pose fixed:        batch %.3f mm, bound %.3f mm, ratio %.3f\n"
              "  after similarity (Horn): batch %.3f mm, bound %.3f mm, ratio %.3f\n",
              trials, noise, 1e3 * error_rms, 1e3 * bound.rms_fixed_first_pose_m,
              error_rms / bound.rms_fixed_first_pose_m, 1e3 * aligned_rms,
              1e3 * bound.rms_after_similarity_m, aligned_rms / bound.rms_after_similarity_m);
  return 0;
}
