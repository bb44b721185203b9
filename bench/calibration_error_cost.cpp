// What a calibration's error costs shape-from-motion, and what [sfm] refine_camera gives back
// (not a benchmark: a table). Each scenario's true rig moved by a draw from a calibration's
// reported covariance (the [omni_camera_covariance] of a calibrated camera file, its sigmas times
// SIGMA_FACTOR); the batch's error against the truth after a similarity alignment with the exact
// camera, the calibrated one, and the calibrated one refined under that covariance
// (BatchSettings::camera_prior), per seed; the camera's distance from the truth in the
// covariance's sigmas before and after, and the refined parameters' NEES under the batch's own
// covariance; then per scenario the median and worst ratios to the exact camera's errors (the
// refined ones over the seeds where the camera was refined) and the refined parameters' mean
// NEES.
// KNOWN_DISTANCE 1: every solve is told the true distance from the first camera position to the
// last (known_distance_m), which holds the scale there and lets the camera be refined where the
// images alone do not fix the scale.
//   calibration_error_cost CALIBRATED_CAMERA.ini [SEEDS=10] [SIGMA_FACTOR=1] [FIRST_SEED=1]
//                          [KNOWN_DISTANCE=0]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "omnisfm/core/percentile.h"
#include "omnisfm/eval/calibration_error.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sfm/settings_file.h"
#include "omnisfm/sim/scenario.h"

namespace {

using namespace omnisfm;

// With `known_distance`, the batch is told the true distance from the first camera position to
// the last (sfm's known_distance_m), as a user with a tape would.
sfm::SfmResult solved(const camera::CatadioptricCamera& camera, const sim::Dataset& d,
                      const sfm::CameraPrior& prior, bool known_distance) {
  sfm::SfmSettings settings;
  settings.batch.camera_prior = prior;
  if (known_distance)
    settings.batch.known_distance_m =
        (d.world_from_cam.back().translation() - d.world_from_cam.front().translation()).norm();
  return sfm::run_sfm(camera, d.observations, settings);
}

eval::TrajectoryErrors errors(const sfm::SfmResult& r, const sim::Dataset& d) {
  return eval::trajectory_errors(r.batch.world_from_cam, d.world_from_cam, true);
}

double median(const std::vector<double>& v) { return v.empty() ? NAN : core::percentile(v, 0.5); }

double worst(const std::vector<double>& v) {
  return v.empty() ? NAN : *std::max_element(v.begin(), v.end());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: calibration_error_cost CALIBRATED_CAMERA.ini [SEEDS] [SIGMA_FACTOR] "
                 "[FIRST_SEED] [KNOWN_DISTANCE]\n");
    return 2;
  }
  sfm::use_one_blas_thread();
  const auto covariance = io::read_camera_covariance(argv[1]);
  if (!covariance) {
    std::fprintf(stderr, "%s: no [omni_camera_covariance]\n", argv[1]);
    return 2;
  }
  const int seeds = argc > 2 ? std::atoi(argv[2]) : 10;
  const double factor = argc > 3 ? std::atof(argv[3]) : 1;
  const int first_seed = argc > 4 ? std::atoi(argv[4]) : 1;
  const bool known_distance = argc > 5 && std::atoi(argv[5]) != 0;
  std::printf("# scenario seed exact_percent exact_deg calibrated_percent calibrated_deg "
              "refined_percent refined_deg sigmas_calibrated sigmas_refined nees_refined\n");
  for (const char* scenario : {"lab", "crane", "rover"}) {
    std::vector<double> calibrated_percent, calibrated_deg, refined_percent, refined_deg,
        refined_nees;
    for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
      sim::SimulationOptions options;
      options.scenario = scenario;
      options.seed = static_cast<std::uint64_t>(seed);
      const sim::Dataset d = sim::simulate(options);
      sfm::CameraPrior prior = sfm::camera_prior_from(d.camera, *covariance);
      prior.covariance *= factor * factor;
      const camera::CatadioptricCamera calibrated =
          eval::calibrated_with_error(d.camera, prior, 1000 + seed);
      const auto exact = errors(solved(d.camera, d, {}, known_distance), d);
      const auto held = errors(solved(calibrated, d, {}, known_distance), d);
      const sfm::SfmResult refinement = solved(calibrated, d, prior, known_distance);
      const auto refined = errors(refinement, d);
      // Where the batch held the scale, and the camera with it: NaN, and the calibrated camera.
      const bool was_refined = refinement.batch.camera_refined;
      const double nees =
          was_refined ? std::pow(eval::sigmas_from_truth(refinement.batch.camera_params, d.camera,
                                                         prior, refinement.batch.camera_covariance),
                                 2)
                      : NAN;
      const double sigmas_calibrated =
          eval::sigmas_from_truth(calibrated.params(), d.camera, prior, prior.covariance);
      const double sigmas_refined =
          was_refined ? eval::sigmas_from_truth(refinement.batch.camera_params, d.camera, prior,
                                                prior.covariance)
                      : sigmas_calibrated;
      std::printf("%s %d %.4f %.4f %.4f %.4f %.4f %.4f %.2f %.2f %.2f\n", scenario, seed,
                  exact.translation_error_percent, exact.mean_rotation_error_deg,
                  held.translation_error_percent, held.mean_rotation_error_deg,
                  refined.translation_error_percent, refined.mean_rotation_error_deg,
                  sigmas_calibrated, sigmas_refined, nees);
      std::fflush(stdout);
      calibrated_percent.push_back(held.translation_error_percent /
                                   exact.translation_error_percent);
      calibrated_deg.push_back(held.mean_rotation_error_deg / exact.mean_rotation_error_deg);
      if (!was_refined) continue;  // the calibrated camera's again
      refined_percent.push_back(refined.translation_error_percent /
                                exact.translation_error_percent);
      refined_deg.push_back(refined.mean_rotation_error_deg / exact.mean_rotation_error_deg);
      refined_nees.push_back(nees);
    }
    double mean_nees = 0;
    for (double n : refined_nees) mean_nees += n / static_cast<double>(refined_nees.size());
    std::printf("# %s / exact camera's: calibrated translation median %.2f worst %.2f, rotation "
                "median %.2f worst %.2f; refined on %zu seeds: translation median %.2f worst "
                "%.2f, rotation median %.2f worst %.2f, mean NEES %.2f\n",
                scenario, median(calibrated_percent), worst(calibrated_percent),
                median(calibrated_deg), worst(calibrated_deg), refined_percent.size(),
                median(refined_percent), worst(refined_percent), median(refined_deg),
                worst(refined_deg), refined_nees.empty() ? NAN : mean_nees);
  }
}
