#include "omnisfm/eval/filter_consistency.h"

#include "omnisfm/eval/calibration_error.h"
#include "omnisfm/eval/filter_run.h"
#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::eval {

Eigen::Matrix<double, 6, 1> filter_pose_error(const Eigen::Isometry3d& true_cam_from_world,
                                              const Eigen::Isometry3d& estimated_cam_from_world) {
  const Eigen::AngleAxisd rotation(true_cam_from_world.linear() *
                                   estimated_cam_from_world.linear().transpose());
  Eigen::Matrix<double, 6, 1> e;
  e << rotation.angle() * rotation.axis(),
      true_cam_from_world.translation() - estimated_cam_from_world.translation();
  return e;
}

PoseConsistency rover_pose_consistency(int seeds, double wheel_scale_error,
                                       const sfm::FilterSettings& settings,
                                       bool linearised_at_truth,
                                       const sfm::CameraPrior* calibration_error,
                                       double error_sigmas) {
  double sum = 0;
  long inside = 0;
  PoseConsistency c;
  for (int seed = 1; seed <= seeds; ++seed) {
    sim::SimulationOptions simulation;
    simulation.scenario = "rover";
    simulation.seed = static_cast<std::uint64_t>(seed);
    const sim::Dataset d = sim::simulate(simulation);
    sim::DeadReckoningOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.odometry_scale_error = wheel_scale_error;
    const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(d, options);
    const sfm::MotionSensors sensors = motion_sensors(&dead_reckoning, options, nullptr);
    camera::CatadioptricCamera camera = d.camera;
    if (calibration_error) {
      sfm::CameraPrior scaled = *calibration_error;
      scaled.covariance *= error_sigmas * error_sigmas;
      camera = calibrated_with_error(d.camera, scaled, 1000 + static_cast<std::uint64_t>(seed));
    }
    sfm::OnlineFilter filter(camera, settings);
    if (linearised_at_truth) {
      const Eigen::Isometry3d first = d.world_from_cam[0];
      filter.linearise_at({[&d, first](int frame) { return d.world_from_cam[frame].inverse() * first; },
                           [&d, first](int track) { return (first.inverse() * d.track_points[track]).eval(); }});
    }
    run_filter(d, &sensors, settings, &filter, [&](int f) {
      if (f == 0) return;
      const Eigen::Isometry3d truth = d.world_from_cam[f].inverse() * d.world_from_cam[0];
      const Eigen::Matrix<double, 6, 1> e = filter_pose_error(truth, filter.cam_from_world());
      const double nees = e.dot(filter.pose_covariance().ldlt().solve(e));
      sum += nees;
      ++c.frames;
      inside += nees < 12.59;
    });
  }
  c.mean_nees = sum / static_cast<double>(c.frames);
  c.inside = static_cast<double>(inside) / static_cast<double>(c.frames);
  return c;
}

}  // namespace omnisfm::eval
