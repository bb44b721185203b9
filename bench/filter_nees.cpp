// The filter's published pose covariance against its actual errors (not a benchmark: one run,
// one line): the normalised estimation error squared (NEES) of the pose at every frame over the
// simulated rover's seeds, with the simulated odometry and gyro and their noise models, the
// pose's error as the covariance states it (rotation as a left perturbation, then translation,
// of cam_from_world, the gauge the first frame's). Honest: a mean of 6 and 95 % of frames inside
// chi-square(6)'s 95 % bound (12.59).
//   filter_nees [SEEDS=25] [WHEEL_SCALE_ERROR=0.015]
// WHEEL_SCALE_ERROR: how long the simulated wheel reads (the filter takes the calibration as
// exact unless FilterSettings::estimate_wheel_scale).

#include <cstdio>
#include <cstdlib>

#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/scenario.h"

int main(int argc, char** argv) {
  using namespace omnisfm;
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 25;
  const double wheel_error = argc > 2 ? std::atof(argv[2]) : 0.015;
  double sum = 0;
  long frames = 0, inside = 0;
  for (int seed = 1; seed <= seeds; ++seed) {
    sim::SimulationOptions simulation;
    simulation.scenario = "rover";
    simulation.seed = static_cast<std::uint64_t>(seed);
    const sim::Dataset d = sim::simulate(simulation);
    sim::DeadReckoningOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.odometry_scale_error = wheel_error;
    const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(d, options);
    const sfm::MotionSensors sensors = eval::motion_sensors(&dead_reckoning, options, nullptr);
    const sfm::FilterSettings settings;
    sfm::OnlineFilter filter(d.camera, settings);
    const auto by_frame = sfm::observations_by_frame(d.observations);
    filter.process_frame(0, by_frame[0]);
    for (size_t f = 1; f < by_frame.size(); ++f) {
      filter.process_frame(static_cast<int>(f), by_frame[f],
                           sfm::predict_camera_motion(sensors, d.timestamps[f - 1], d.timestamps[f],
                                                      settings, filter.sensor_states()));
      const Eigen::Isometry3d truth = d.world_from_cam[f].inverse() * d.world_from_cam[0];
      const Eigen::Isometry3d estimate = filter.cam_from_world();
      const Eigen::AngleAxisd rotation(truth.linear() * estimate.linear().transpose());
      Eigen::Matrix<double, 6, 1> e;
      e << rotation.angle() * rotation.axis(), truth.translation() - estimate.translation();
      const double nees = e.dot(filter.pose_covariance().ldlt().solve(e));
      sum += nees;
      ++frames;
      inside += nees < 12.59;
    }
  }
  std::printf("rover seeds 1-%d, wheel reading %+.1f %%: mean NEES %.2f (6 when honest), %.1f %% "
              "of %ld frames inside the 95 %% bound\n",
              seeds, 100 * wheel_error, sum / static_cast<double>(frames),
              100.0 * static_cast<double>(inside) / static_cast<double>(frames), frames);
}
