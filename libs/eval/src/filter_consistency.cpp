#include "omnisfm/eval/filter_consistency.h"

#include <algorithm>
#include <cmath>

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

PoseConsistency rover_pose_consistency(int seeds, const sfm::FilterSettings& settings,
                                       const RoverStudy& study) {
  double sum = 0, scale_sum = 0, linearised_sum = 0;
  long inside = 0;
  PoseConsistency c;
  c.smallest_scale = INFINITY;
  for (int seed = 1; seed <= seeds; ++seed) {
    sim::SimulationOptions simulation;
    simulation.scenario = "rover";
    simulation.seed = static_cast<std::uint64_t>(seed);
    const sim::Dataset d = sim::simulate(simulation);
    sim::DeadReckoningOptions options;
    options.seed = static_cast<std::uint64_t>(seed);
    options.odometry_scale_error = study.wheel_scale_error;
    const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(d, options);
    const sfm::MotionSensors sensors = motion_sensors(&dead_reckoning, options, nullptr);
    camera::CatadioptricCamera camera = d.camera;
    if (study.calibration_error) {
      sfm::CameraPrior scaled = *study.calibration_error;
      scaled.covariance *= study.error_sigmas * study.error_sigmas;
      camera = calibrated_with_error(d.camera, scaled, 1000 + static_cast<std::uint64_t>(seed));
    }
    sfm::OnlineFilter filter(camera, settings);
    if (study.linearised_at_truth) {
      const Eigen::Isometry3d first = d.world_from_cam[0];
      filter.linearise_at({[&d, first](int frame) { return d.world_from_cam[frame].inverse() * first; },
                           [&d, first](int track) { return (first.inverse() * d.track_points[track]).eval(); }});
    }
    run_filter(d, study.with_sensors ? &sensors : nullptr, settings, &filter, [&](int f) {
      if (f == 0) return;
      const Eigen::Isometry3d truth = d.world_from_cam[f].inverse() * d.world_from_cam[0];
      const Eigen::Matrix<double, 6, 1> e = filter_pose_error(truth, filter.cam_from_world());
      const double nees = e.dot(filter.pose_covariance().ldlt().solve(e));
      sum += nees;
      ++c.frames;
      inside += nees < 12.59;
    });
    if (const double sigma = filter.vision_scale_log_sigma(); sigma > 0) {
      const Eigen::Isometry3d last = d.world_from_cam.back().inverse() * d.world_from_cam[0];
      const double scale =
          filter.cam_from_world().translation().norm() / last.translation().norm();
      scale_sum += std::pow(std::log(scale) / sigma, 2);
      linearised_sum += std::pow((1 - 1 / scale) / sigma, 2);
      c.largest_scale = std::max(c.largest_scale, scale);
      c.smallest_scale = std::min(c.smallest_scale, scale);
    }
  }
  c.mean_scale_nees = scale_sum / seeds;
  c.mean_linearised_scale_nees = linearised_sum / seeds;
  if (c.largest_scale == 0) c.smallest_scale = 0;
  c.mean_nees = sum / static_cast<double>(c.frames);
  c.inside = static_cast<double>(inside) / static_cast<double>(c.frames);
  return c;
}

}  // namespace omnisfm::eval
