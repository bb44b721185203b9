// The filter's published pose covariance against its actual errors (not a benchmark: one run,
// one line), eval::rover_pose_consistency over the simulated rover's seeds.
//   filter_nees [SEEDS=25] [WHEEL_SCALE_ERROR=0.015] [ESTIMATE_WHEEL_SCALE=1] [AT_TRUTH=0]
//               [PREDICTED_SETTLE_SIGMAS=0.3]
// WHEEL_SCALE_ERROR: how long the simulated wheel reads (the filter takes the calibration as
// exact when ESTIMATE_WHEEL_SCALE is 0: FilterSettings::estimate_wheel_scale). AT_TRUTH 1: the
// filter linearised at the truth (OnlineFilter::linearise_at), Huang et al.'s ideal EKF.
// PREDICTED_SETTLE_SIGMAS: FilterSettings::predicted_settle_sigmas.

#include <cstdio>
#include <cstdlib>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/sfm/blas_threads.h"

int main(int argc, char** argv) {
  omnisfm::sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 25;
  const double wheel_error = argc > 2 ? std::atof(argv[2]) : 0.015;
  omnisfm::sfm::FilterSettings settings;
  if (argc > 3) settings.estimate_wheel_scale = std::atoi(argv[3]) != 0;
  const bool at_truth = argc > 4 && std::atoi(argv[4]) != 0;
  if (argc > 5) settings.predicted_settle_sigmas = std::atof(argv[5]);
  const omnisfm::eval::PoseConsistency c =
      omnisfm::eval::rover_pose_consistency(seeds, wheel_error, settings, at_truth);
  std::printf("rover seeds 1-%d, wheel reading %+.1f %%%s%s: mean NEES %.2f (6 when honest), %.1f %% "
              "of %ld frames inside the 95 %% bound\n",
              seeds, 100 * wheel_error,
              settings.estimate_wheel_scale ? ", its scale estimated" : "",
              at_truth ? ", linearised at the truth" : "", c.mean_nees,
              100 * c.inside, c.frames);
}
