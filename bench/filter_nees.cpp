// The filter's published pose covariance against its actual errors (not a benchmark: one run,
// one line), eval::rover_pose_consistency over the simulated rover's seeds.
//   filter_nees [SEEDS=25] [WHEEL_SCALE_ERROR=0.015] [ESTIMATE_WHEEL_SCALE=1] [AT_TRUTH=0]
//               [PREDICTED_SETTLE_SIGMAS=0.3] [CAL.ini|- [ERROR_SIGMAS=1] [CONSIDER=1]] [SENSORS=1]
// WHEEL_SCALE_ERROR: how long the simulated wheel reads (the filter takes the calibration as
// exact when ESTIMATE_WHEEL_SCALE is 0: FilterSettings::estimate_wheel_scale). AT_TRUTH 1: the
// filter linearised at the truth (OnlineFilter::linearise_at), Huang et al.'s ideal EKF.
// PREDICTED_SETTLE_SIGMAS: FilterSettings::predicted_settle_sigmas.
// CAL.ini: a camera file with [omni_camera_covariance] (omnisfm calibrate's); the filter's camera
// is then the rover's with an error drawn from that covariance times ERROR_SIGMAS, seed by seed,
// and with CONSIDER 1 the filter is given the covariance (FilterSettings::camera_uncertainty).
// SENSORS 0: the camera alone (its covariance then holds the map's scale).

#include <cstdio>
#include <cstdlib>
#include <string>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sfm/settings_file.h"
#include "omnisfm/sim/scenario.h"

int main(int argc, char** argv) {
  using namespace omnisfm;
  sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 25;
  const double wheel_error = argc > 2 ? std::atof(argv[2]) : 0.015;
  sfm::FilterSettings settings;
  if (argc > 3) settings.estimate_wheel_scale = std::atoi(argv[3]) != 0;
  const bool at_truth = argc > 4 && std::atoi(argv[4]) != 0;
  if (argc > 5) settings.predicted_settle_sigmas = std::atof(argv[5]);
  const bool calibrated = argc > 6 && std::string(argv[6]) != "-";
  const double error_sigmas = argc > 7 ? std::atof(argv[7]) : 1;
  const bool consider = calibrated && (argc <= 8 || std::atoi(argv[8]) != 0);
  const bool with_sensors = argc <= 9 || std::atoi(argv[9]) != 0;
  sfm::CameraPrior calibration;
  if (calibrated) {
    const auto covariance = io::read_camera_covariance(argv[6]);
    if (!covariance) {
      std::fprintf(stderr, "%s: no [omni_camera_covariance]\n", argv[6]);
      return 2;
    }
    sim::SimulationOptions rover;
    rover.scenario = "rover";
    calibration = sfm::camera_prior_from(sim::simulate(rover).camera, *covariance);
    if (consider) settings.camera_uncertainty = calibration;
  }
  eval::RoverStudy study;
  study.wheel_scale_error = wheel_error;
  study.with_sensors = with_sensors;
  study.linearised_at_truth = at_truth;
  study.calibration_error = calibrated ? &calibration : nullptr;
  study.error_sigmas = error_sigmas;
  const eval::PoseConsistency c = eval::rover_pose_consistency(seeds, settings, study);
  std::string camera = "";
  if (calibrated)
    camera = ", camera " + std::to_string(error_sigmas).substr(0, 4) + " sigmas off" +
             (consider ? " and its covariance considered" : " and taken as exact");
  std::string inputs = "the camera alone";
  if (with_sensors) {
    char wheel[96];
    std::snprintf(wheel, sizeof wheel, "wheel reading %+.1f %%%s", 100 * wheel_error,
                  settings.estimate_wheel_scale ? ", its scale estimated" : "");
    inputs = wheel;
  }
  std::printf("rover seeds 1-%d, %s%s%s: mean NEES %.2f (6 when honest), "
              "%.1f %% of %ld frames inside the 95 %% bound\n",
              seeds, inputs.c_str(), at_truth ? ", linearised at the truth" : "", camera.c_str(), c.mean_nees,
              100 * c.inside, c.frames);
  if (!with_sensors)
    std::printf("the map's scale at the last frame %.2f-%.2f, its log's mean square over the "
                "published sigma %.2f (1 when honest)\n",
                c.smallest_scale, c.largest_scale, c.mean_scale_nees);
}
