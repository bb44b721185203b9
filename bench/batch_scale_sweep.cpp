// The batch's scale over seeds of the lab, crane and rover (not a benchmark: one run, one table):
// each seed's scale after a similarity alignment onto the truth (estimate length / true length),
// the filter's, and the batch's as the pipeline leaves it (free or held) next to the batch with
// every scale kept free (as it was before the hold). Then, per experiment, how many were held, the
// worst free scale, and the free scales' errors against their reported standard deviations.
//   batch_scale_sweep [LAST_SEED=25] [FIRST_SEED=1]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sfm/blas_threads.h"

namespace {

using namespace omnisfm;

// Estimated length per true length.
double scale_of(const std::vector<Eigen::Isometry3d>& world_from_cam, const sim::Dataset& d) {
  return 1 / eval::trajectory_errors(world_from_cam, d.world_from_cam, true).alignment.scale;
}

const char* name_of(sfm::BatchScale scale) {
  switch (scale) {
    case sfm::BatchScale::kFromImages: return "free";
    case sfm::BatchScale::kHeldAtStart: return "held";
    case sfm::BatchScale::kHeldAtKnownDistance: return "known";
    case sfm::BatchScale::kFromSensors: return "sensors";
    case sfm::BatchScale::kNoTranslation: return "none";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  omnisfm::sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  const int last_seed = argc > 1 ? std::atoi(argv[1]) : 25;
  const int first_seed = argc > 2 ? std::atoi(argv[2]) : 1;
  std::printf("# scenario seed filter_scale free_scale free_sigma scale sigma status z\n");
  std::string summary;
  for (const char* scenario : {"lab", "crane", "rover"}) {
    int runs = 0, held = 0, free_beyond_2x = 0, before_beyond_2x = 0, beyond_3_sigma = 0;
    double worst_free = 1, worst_before = 1, sum_z2 = 0, worst_z = 0;
    std::vector<double> abs_z;
    for (int seed = first_seed; seed <= last_seed; ++seed) {
      sim::SimulationOptions options;
      options.scenario = scenario;
      options.seed = static_cast<std::uint64_t>(seed);
      const sim::Dataset d = sim::simulate(options);
      sfm::SfmSettings settings;
      settings.batch.covariances = false;
      const sfm::SfmResult r = sfm::run_sfm(d.camera, d.observations, settings);
      sfm::SfmSettings free_settings = settings;
      free_settings.batch.max_free_scale_sigma = std::numeric_limits<double>::infinity();
      const sfm::SfmResult before = sfm::run_sfm(d.camera, d.observations, free_settings);

      const double filter = scale_of(r.online_world_from_cam, d);
      const double scale = scale_of(r.batch.world_from_cam, d);
      const double free_scale = scale_of(before.batch.world_from_cam, d);
      const double factor = std::max(scale, 1 / scale);
      const double before_factor = std::max(free_scale, 1 / free_scale);
      worst_before = std::max(worst_before, before_factor);
      if (before_factor > 2) ++before_beyond_2x;
      ++runs;
      // The error in the inverse scale, which the reported sigma describes.
      const double z = (1 / scale - 1) / r.batch.scale_sigma_relative;
      if (r.batch.scale_source == sfm::BatchScale::kFromImages) {
        worst_free = std::max(worst_free, factor);
        if (factor > 2) ++free_beyond_2x;
        sum_z2 += z * z;
        abs_z.push_back(std::abs(z));
        worst_z = std::max(worst_z, std::abs(z));
        if (std::abs(z) > 3) ++beyond_3_sigma;
      } else {
        ++held;
      }
      std::printf("%s %d %.4g %.4g %.3g %.4g %.3g %s %.2f\n", scenario, seed, filter, free_scale,
                  before.batch.scale_sigma_relative, scale, r.batch.scale_sigma_relative,
                  name_of(r.batch.scale_source), z);
      std::fflush(stdout);
    }
    std::sort(abs_z.begin(), abs_z.end());
    const int kept = runs - held;
    char line[512];
    std::snprintf(line, sizeof line,
                  "# %s: %d seeds; before: %d beyond 2x, worst %.3gx; now %d held, %d free "
                  "(%d beyond 2x, worst %.3gx); free |error| / sigma: RMS %.2f, median %.2f, worst "
                  "%.2f, %d beyond 3\n",
                  scenario, runs, before_beyond_2x, worst_before, held, kept, free_beyond_2x,
                  worst_free, kept ? std::sqrt(sum_z2 / kept) : NAN,
                  kept ? abs_z[abs_z.size() / 2] : NAN, worst_z, beyond_3_sigma);
    summary += line;
  }
  std::printf("%s", summary.c_str());
  return 0;
}
