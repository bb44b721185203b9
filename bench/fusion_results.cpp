// Fusion results for the README (not a benchmark: one run, one table): on the simulated rover at
// the default noise, the estimators' noise models the simulation's, over a few seeds, dead
// reckoning alone, vision alone and vision fused with the odometry and the gyro (with the wheel
// reading long, short, or its scale left free; with GPS), each against the ground truth:
//   - scale error: |1/s - 1| of the similarity that best aligns the estimate (the estimate's own
//     scale against the truth's);
//   - translation error after a rigid alignment (no scale), mean, in % of the distance travelled;
//   - yaw error after that alignment, mean, degrees;
//   - with GPS, the mean camera position error in the ENU frame with no alignment at all.
// Usage:
//   fusion_results [SEEDS=3]

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/frame_motion.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sfm/blas_threads.h"

namespace {

using namespace omnisfm;
using Poses = std::vector<Eigen::Isometry3d>;

// world_from_cam by dead reckoning: the odometry's increments between frames, turned by the
// odometry's own heading or by the integrated gyro (its bias not known).
Poses dead_reckoning(const sfm::MotionSensors& sensors, const std::vector<double>& times,
                     bool gyro_heading) {
  const auto motions = sfm::frame_motions(sensors, times, Eigen::Vector3d::Zero());
  Eigen::Isometry3d world_from_body = Eigen::Isometry3d::Identity();
  Poses out{world_from_body * sensors.body_from_cam};
  for (const auto& m : motions) {
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    step.translation() << m.odometry.delta.head<2>(), 0;
    step.linear() = gyro_heading ? m.gyro.rotation
                                 : Eigen::AngleAxisd(m.odometry.delta.z(), Eigen::Vector3d::UnitZ())
                                       .toRotationMatrix();
    world_from_body = world_from_body * step;
    out.push_back(world_from_body * sensors.body_from_cam);
  }
  return out;
}

struct Figures {
  double scale_percent = 0, rigid_percent = 0, yaw_deg = 0, enu_m = NAN;
};

Figures figures(const Poses& world_from_cam, const Poses& truth) {
  const auto similarity = eval::trajectory_errors(world_from_cam, truth, true);
  const auto rigid = eval::trajectory_errors(world_from_cam, truth, false);
  return {100 * std::abs(1 / similarity.alignment.scale - 1), rigid.translation_error_percent,
          rigid.mean_yaw_error_deg};
}

struct Row {
  std::string name;
  std::vector<Figures> runs;
};

std::string cell(const std::vector<Figures>& runs, const std::function<double(const Figures&)>& f,
                 const char* format) {
  double sum = 0, worst = 0;
  for (const auto& r : runs) {
    sum += f(r);
    worst = std::max(worst, f(r));
  }
  if (!std::isfinite(sum)) return "-";
  char mean_text[32], worst_text[32];
  std::snprintf(mean_text, sizeof mean_text, format, sum / runs.size());
  std::snprintf(worst_text, sizeof worst_text, format, worst);
  return std::string(mean_text) + " (" + worst_text + ")";
}

}  // namespace

int main(int argc, char** argv) {
  omnisfm::sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  const int seeds = argc > 1 ? std::atoi(argv[1]) : 3;
  if (seeds < 1) {
    std::fprintf(stderr, "usage: fusion_results [SEEDS=3]\n");
    return 2;
  }
  std::vector<Row> rows = {{"dead reckoning: odometry", {}},
                           {"dead reckoning: odometry + gyro heading", {}},
                           {"vision alone (batch)", {}},
                           {"fused odometry + gyro, online", {}},
                           {"fused odometry + gyro (batch)", {}},
                           {"fused odometry + gyro (batch), a wheel reading 1.5 % short", {}},
                           {"fused odometry + gyro (batch), the wheel's scale left free", {}},
                           {"fused odometry + gyro + GPS (batch, ENU)", {}},
                           {"fused odometry (scale from the GPS run) + gyro (batch)", {}}};
  sfm::SfmSettings settings;
  settings.batch.covariances = false;
  settings.filter.pixel_sigma = 0.2;  // the simulated tracks' noise, as the sensors' are theirs
  for (int seed = 1; seed <= seeds; ++seed) {
    sim::SimulationOptions options;
    options.scenario = "rover";
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    sim::DeadReckoningOptions dr_options;
    dr_options.seed = seed;
    const sim::DeadReckoning dr = sim::simulate_dead_reckoning(d, dr_options);
    sim::GpsOptions gps_options;
    gps_options.seed = seed;
    const sim::GpsTrack gps = sim::simulate_gps(d, gps_options);
    const sfm::MotionSensors sensors = eval::motion_sensors(&dr, dr_options, nullptr);
    const Poses& truth = d.world_from_cam;

    rows[0].runs.push_back(figures(dead_reckoning(sensors, d.timestamps, false), truth));
    rows[1].runs.push_back(figures(dead_reckoning(sensors, d.timestamps, true), truth));
    const auto vision = sfm::run_sfm(d.camera, d.observations, settings);
    rows[2].runs.push_back(figures(vision.batch.world_from_cam, truth));
    const auto fused = sfm::run_fused_sfm(d.camera, d.observations, d.timestamps, sensors, settings);
    rows[3].runs.push_back(figures(fused.online_world_from_cam, truth));
    rows[4].runs.push_back(figures(fused.batch.world_from_cam, truth));
    // The fused scale errs with the wheel whichever way the wheel errs.
    sim::DeadReckoningOptions short_options = dr_options;
    short_options.odometry_scale_error = -dr_options.odometry_scale_error;
    const sim::DeadReckoning short_dr = sim::simulate_dead_reckoning(d, short_options);
    const auto short_fused = sfm::run_fused_sfm(d.camera, d.observations, d.timestamps,
                                                eval::motion_sensors(&short_dr, short_options, nullptr),
                                                settings);
    rows[5].runs.push_back(figures(short_fused.batch.world_from_cam, truth));
    // What the camera alone says of the scale once the motion sensors hold the shape.
    sfm::MotionSensors free_scale = sensors;
    free_scale.odometry_noise.scale_sigma = 1e3;
    const auto free_fused =
        sfm::run_fused_sfm(d.camera, d.observations, d.timestamps, free_scale, settings);
    rows[6].runs.push_back(figures(free_fused.batch.world_from_cam, truth));

    const sfm::MotionSensors with_gps = eval::motion_sensors(&dr, dr_options, &gps);
    const auto enu = sfm::run_fused_sfm(d.camera, d.observations, d.timestamps, with_gps, settings);
    Poses truth_enu;
    for (const auto& T : truth) truth_enu.push_back(gps.enu_from_world * T);
    Figures f = figures(enu.batch.world_from_cam, truth_enu);
    f.enu_m = 0;
    for (size_t k = 0; k < truth.size(); ++k)
      f.enu_m += (enu.batch.world_from_cam[k].translation() - truth_enu[k].translation()).norm() /
                 truth.size();
    rows[7].runs.push_back(f);

    // The next seed's drive takes this one's scale: the same vehicle calibrated on an earlier run.
    sim::SimulationOptions next_options = options;
    next_options.seed = seed + 100;
    const sim::Dataset next = sim::simulate(next_options);
    sim::DeadReckoningOptions next_dr_options = dr_options;
    next_dr_options.seed = seed + 100;
    const sim::DeadReckoning next_dr = sim::simulate_dead_reckoning(next, next_dr_options);
    sfm::MotionSensors calibrated = eval::motion_sensors(&next_dr, next_dr_options, nullptr);
    calibrated.odometry_scale = enu.odometry_scale;
    calibrated.odometry_noise.scale_sigma = 0.003;
    const auto later = sfm::run_fused_sfm(next.camera, next.observations, next.timestamps, calibrated, settings);
    rows[8].runs.push_back(figures(later.batch.world_from_cam, next.world_from_cam));
    std::fprintf(stderr, "seed %d: odometry scale from GPS %.5f (truth %.5f)\n", seed,
                 enu.odometry_scale, 1 / (1 + dr_options.odometry_scale_error));
  }
  std::printf("| estimate | scale error %% | translation error, rigid alignment, %% of distance | yaw error, deg | position error in ENU, m |\n");
  std::printf("| --- | --- | --- | --- | --- |\n");
  for (const auto& row : rows)
    std::printf("| %s | %s | %s | %s | %s |\n", row.name.c_str(),
                cell(row.runs, [](const Figures& f) { return f.scale_percent; }, "%.2f").c_str(),
                cell(row.runs, [](const Figures& f) { return f.rigid_percent; }, "%.3f").c_str(),
                cell(row.runs, [](const Figures& f) { return f.yaw_deg; }, "%.3f").c_str(),
                cell(row.runs, [](const Figures& f) { return f.enu_m; }, "%.4f").c_str());
  std::printf("\nmean (worst) over seeds 1-%d\n", seeds);
  return 0;
}
