// The filter's published pose covariance against its errors along a long drive (not a benchmark:
// one run, a line per block): sim::long_drive with the simulated odometry and gyro, fed to
// OnlineFilter as run_fused_sfm does. Per block of frames: the orientation's and position's errors
// and published sigmas, the mean NEES and its rotation and translation parts (3 each when
// honest), the wheels' scale, how far the direction of travel over 30-frame spans is from the
// true one (in the camera's frame) and the estimated over the true length of those spans (the
// map's scale); at the end the drive's error after a rigid alignment and after a similarity.
// SENSORS 0: the camera alone (the random walk; the NEES then ignores the scale). ORIGIN: when the
// state's origin follows the camera (FilterSettings::origin_follows_camera), 0 never, 1 vision
// alone, 2 always. TAKE_BACK 0: the depth priors kept (FilterSettings::take_back_depth_priors).
// CAMERA.ini: another rig than the simulator's (its mirror below the camera, as the drive needs).
// NAME=VALUE, anywhere: the tracks' noise (noise=0.2 px); which inputs the filter gets (vision,
// gyro, odometry: 0 or 1; axes=1 adds a line per block with the rotation's error and sigma about
// each of the camera's axes, z up, and about the first frame's; noisy_before_age=A or
// noisy_from_age=A: the noise only on each track's observations less than A frames after its first,
// or only on the others, the rest exact); the simulated sensors' noise (gyro_noise_density,
// gyro_bias_sigma, gyro_bias_walk, odometry_position_noise, odometry_heading_noise); or a setting
// of the filter (pixel_sigma, rotation_walk_sigma, translation_walk_sigma, initial_depth,
// inverse_depth_sigma, predicted_settle_sigmas, outlier_chi2, smoothed_start_frames,
// wheel_scale_from_images, origin_turns: 0 never, 1 with the sensors, 2 always; update_iterations,
// linearise_at_constant_velocity,
// measure_noise, smoothing_window_frames: the sliding window, 0 off). With the window, the solves
// it took and refused are printed at the end.
//   drive_nees [FRAMES=20000] [SEED=1] [BLOCK=2000] [WHEEL_SCALE_ERROR=0.015]
//              [ESTIMATE_WHEEL_SCALE=1] [SENSORS=1] [ORIGIN=2] [TAKE_BACK=1] [CAMERA.ini]
//              [NAME=VALUE...]

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/eval/filter_run.h"
#include "omnisfm/eval/simulated_sensors.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/endless_drive.h"
#include "setting_assignment.h"

namespace {

constexpr int kSpan = 30;  // frames: a track's life on the drive

// The estimated over the true distance from frame f to f + kSpan: the map's scale there.
double travel_scale(const std::vector<Eigen::Isometry3d>& estimate,
                    const std::vector<Eigen::Isometry3d>& truth, int f) {
  const auto length = [f](const std::vector<Eigen::Isometry3d>& poses) {
    return (poses[f + kSpan].translation() - poses[f].translation()).norm();
  };
  return length(estimate) / length(truth);
}

// What a NAME=VALUE argument can set: the simulation's and the filter's settings, and which inputs
// the filter gets.
struct Study {
  omnisfm::sfm::FilterSettings settings;
  omnisfm::sim::DeadReckoningOptions options;
  double pixel_noise = 0.2;
  bool with_vision = true;
  bool with_gyro = true;
  bool with_odometry = true;
  bool per_axis = false;  // the rotation's error and sigma about each of the camera's axes too
  // The noise only on each track's observations from this age on (frames since its first), or
  // only before it; the others exact (0: everywhere).
  int noisy_from_age = 0;
  int noisy_before_age = 0;
};

// Where the tracks' noise moves the filter: `drive`'s pixels set back to `exact`'s (the same drive
// without noise) outside the ages the study keeps noisy. False where the two drives' tracks differ.
bool keep_noise_by_age(const omnisfm::sim::Dataset& exact, const Study& study,
                       omnisfm::sim::Dataset* drive) {
  if (exact.observations.size() != drive->observations.size()) return false;
  std::map<int, int> first_frame;
  for (size_t k = 0; k < drive->observations.size(); ++k) {
    omnisfm::core::TrackObservation& o = drive->observations[k];
    if (o.track != exact.observations[k].track || o.frame != exact.observations[k].frame)
      return false;
    const int age = o.frame - first_frame.emplace(o.track, o.frame).first->second;
    const bool noisy =
        study.noisy_before_age > 0 ? age < study.noisy_before_age : age >= study.noisy_from_age;
    if (!noisy) o.pixel = exact.observations[k].pixel;
  }
  return true;
}

bool apply(const std::string& assignment, Study* study) {
  omnisfm::sfm::FilterSettings& settings = study->settings;
  omnisfm::sim::DeadReckoningOptions& options = study->options;
  const omnisfm::bench::Setters settable = {
      {"noise", [&](double v) { study->pixel_noise = v; }},
      {"vision", [&](double v) { study->with_vision = v != 0; }},
      {"gyro", [&](double v) { study->with_gyro = v != 0; }},
      {"odometry", [&](double v) { study->with_odometry = v != 0; }},
      {"axes", [&](double v) { study->per_axis = v != 0; }},
      {"noisy_from_age", [&](double v) { study->noisy_from_age = static_cast<int>(v); }},
      {"noisy_before_age", [&](double v) { study->noisy_before_age = static_cast<int>(v); }},
      {"gyro_noise_density", [&](double v) { options.gyro_noise_density = v; }},
      {"gyro_bias_sigma", [&](double v) { options.gyro_bias_sigma = v; }},
      {"gyro_bias_walk", [&](double v) { options.gyro_bias_walk = v; }},
      {"odometry_position_noise", [&](double v) { options.odometry_position_noise = v; }},
      {"odometry_heading_noise", [&](double v) { options.odometry_heading_noise = v; }},
      {"pixel_sigma", [&](double v) { settings.pixel_sigma = v; }},
      {"rotation_walk_sigma", [&](double v) { settings.rotation_walk_sigma = v; }},
      {"translation_walk_sigma", [&](double v) { settings.translation_walk_sigma = v; }},
      {"initial_depth", [&](double v) { settings.initial_depth = v; }},
      {"inverse_depth_sigma", [&](double v) { settings.inverse_depth_sigma = v; }},
      {"predicted_settle_sigmas", [&](double v) { settings.predicted_settle_sigmas = v; }},
      {"outlier_chi2", [&](double v) { settings.outlier_chi2 = v; }},
      {"smoothed_start_frames",
       [&](double v) { settings.smoothed_start_frames = static_cast<int>(v); }},
      {"smoothing_window_frames",
       [&](double v) { settings.smoothing_window_frames = static_cast<int>(v); }},
      {"origin_turns",
       [&](double v) {
         settings.origin_turns_with_camera = static_cast<omnisfm::sfm::OriginTurnsWithCamera>(
             std::clamp(static_cast<int>(v), 0, 2));
       }},
      {"wheel_scale_from_images", [&](double v) { settings.wheel_scale_from_images = v != 0; }},
      {"measure_noise", [&](double v) { settings.measure_noise = v != 0; }},
      {"update_iterations", [&](double v) { settings.update_iterations = static_cast<int>(v); }},
      {"linearise_at_constant_velocity",
       [&](double v) { settings.linearise_at_constant_velocity = v != 0; }},
  };
  return omnisfm::bench::apply_assignment(assignment, settable);
}

}  // namespace

int main(int argc_given, char** argv_given) {
  using namespace omnisfm;
  sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  // NAME=VALUE arguments are settings, anywhere; the others are positional.
  std::vector<char*> positional;
  std::vector<std::string> assignments;
  for (int k = 0; k < argc_given; ++k) {
    if (k > 0 && std::strchr(argv_given[k], '='))
      assignments.push_back(argv_given[k]);
    else
      positional.push_back(argv_given[k]);
  }
  const int argc = static_cast<int>(positional.size());
  char** argv = positional.data();
  const int frames = argc > 1 ? std::atoi(argv[1]) : 20000;
  const std::uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  const int block = argc > 3 ? std::max(1, std::atoi(argv[3])) : 2000;
  Study study;
  sim::DeadReckoningOptions& options = study.options;
  sfm::FilterSettings& settings = study.settings;
  options.seed = seed;
  if (argc > 4) options.odometry_scale_error = std::atof(argv[4]);
  if (argc > 5) settings.estimate_wheel_scale = std::atoi(argv[5]) != 0;
  const bool with_sensors = argc > 6 ? std::atoi(argv[6]) != 0 : true;
  if (argc > 7)
    settings.origin_follows_camera =
        static_cast<sfm::OriginFollowsCamera>(std::clamp(std::atoi(argv[7]), 0, 2));
  if (argc > 8) settings.take_back_depth_priors = std::atoi(argv[8]) != 0;
  for (const std::string& assignment : assignments)
    if (!apply(assignment, &study)) {
      std::fprintf(stderr, "drive_nees: unknown setting, or not a number: %s\n",
                   assignment.c_str());
      return 2;
    }

  sim::Dataset drive =
      argc > 9 ? sim::long_drive(frames, study.pixel_noise, seed, io::read_camera_file(argv[9]))
               : sim::long_drive(frames, study.pixel_noise, seed);
  if (study.noisy_from_age != 0 && study.noisy_before_age != 0) {
    std::fprintf(stderr, "drive_nees: noisy_before_age or noisy_from_age, not both\n");
    return 2;
  }
  if (study.noisy_from_age < 0 || study.noisy_before_age < 0) {
    std::fprintf(stderr, "drive_nees: a track's age is 0 or more frames\n");
    return 2;
  }
  if (study.noisy_from_age > 0 || study.noisy_before_age > 0) {
    const sim::Dataset exact =
        argc > 9 ? sim::long_drive(frames, 0.0, seed, io::read_camera_file(argv[9]))
                 : sim::long_drive(frames, 0.0, seed);
    if (!keep_noise_by_age(exact, study, &drive)) {
      std::fprintf(stderr, "drive_nees: the exact drive's tracks differ from the noisy one's\n");
      return 2;
    }
  }
  const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(drive, options);
  sfm::MotionSensors sensors = eval::motion_sensors(&dead_reckoning, options, nullptr);
  if (!study.with_gyro) sensors.gyro.clear();
  if (!study.with_odometry) sensors.odometry.clear();
  if (!study.with_vision)  // the first frame's tracks only, and the last's to keep the length
    drive.observations.erase(std::remove_if(drive.observations.begin(), drive.observations.end(),
                                            [&](const core::TrackObservation& o) {
                                              return o.frame != 0 && o.frame != frames - 1;
                                            }),
                             drive.observations.end());
  sfm::OnlineFilter filter(drive.camera, settings);
  const Eigen::Isometry3d first_from_world = drive.world_from_cam[0].inverse();
  std::vector<Eigen::Isometry3d> estimate;
  double nees = 0, nees_rotation = 0, nees_translation = 0;
  int counted = 0;
  std::printf(
      "# frame rotation_error_deg rotation_sigma_deg position_error_m position_sigma_m "
      "nees nees_rotation nees_translation wheel_scale wheel_scale_sigma "
      "travel_direction_error_deg travel_scale\n");
  eval::run_filter(drive, with_sensors ? &sensors : nullptr, settings, &filter, [&](int f) {
    const Eigen::Isometry3d truth = (first_from_world * drive.world_from_cam[f]).inverse();
    const Eigen::Isometry3d est = filter.cam_from_world();
    estimate.push_back(drive.world_from_cam[0] * est.inverse());
    const Eigen::Matrix<double, 6, 1> e = eval::filter_pose_error(truth, est);
    const Eigen::Matrix<double, 6, 6> P = filter.pose_covariance();
    if (f > 0) {
      nees += e.dot(P.ldlt().solve(e));
      nees_rotation += e.head<3>().dot(P.topLeftCorner<3, 3>().ldlt().solve(e.head<3>()));
      nees_translation += e.tail<3>().dot(P.bottomRightCorner<3, 3>().ldlt().solve(e.tail<3>()));
      ++counted;
    }
    if ((f + 1) % block == 0 && counted > 0) {
      constexpr double kDeg = 180 / M_PI;
      // The spans that end within the block.
      double direction_error = 0, scale = 0;
      int spans = 0;
      for (int g = std::max(0, f + 1 - block - kSpan); g + kSpan <= f; ++g, ++spans) {
        direction_error +=
            eval::travel_direction_error_deg(estimate, drive.world_from_cam, g, kSpan);
        scale += travel_scale(estimate, drive.world_from_cam, g);
      }
      std::printf("%d %.3f %.3f %.3f %.3f %.1f %.1f %.1f %.4f %.4f %.1f %.3f\n", f + 1,
                  e.head<3>().norm() * kDeg, std::sqrt(P.topLeftCorner<3, 3>().trace()) * kDeg,
                  e.tail<3>().norm(), std::sqrt(P.bottomRightCorner<3, 3>().trace()),
                  nees / counted, nees_rotation / counted, nees_translation / counted,
                  filter.wheel_scale(), std::sqrt(filter.wheel_scale_variance()),
                  spans > 0 ? direction_error / spans : NAN, spans > 0 ? scale / spans : NAN);
      if (study.per_axis) {
        // The same error and sigma about the first frame's axes, which stay put as the vehicle
        // turns.
        const Eigen::Matrix3d first_from_cam = truth.linear().transpose();
        const Eigen::Vector3d first_error = first_from_cam * e.head<3>() * kDeg;
        const Eigen::Vector3d first_sigma =
            (first_from_cam * P.topLeftCorner<3, 3>() * first_from_cam.transpose())
                .diagonal()
                .cwiseSqrt() *
            kDeg;
        std::printf(
            "#   about x y z: error %.3f %.3f %.3f deg, sigma %.3f %.3f %.3f deg; about the "
            "first frame's: error %.3f %.3f %.3f deg, sigma %.3f %.3f %.3f deg\n",
            e(0) * kDeg, e(1) * kDeg, e(2) * kDeg, std::sqrt(P(0, 0)) * kDeg,
            std::sqrt(P(1, 1)) * kDeg, std::sqrt(P(2, 2)) * kDeg, first_error.x(), first_error.y(),
            first_error.z(), first_sigma.x(), first_sigma.y(), first_sigma.z());
      }
      nees = nees_rotation = nees_translation = 0;
      counted = 0;
    }
  });
  const std::vector<Eigen::Isometry3d> truth(drive.world_from_cam.begin(),
                                             drive.world_from_cam.begin() + frames);
  const eval::TrajectoryErrors rigid = eval::trajectory_errors(estimate, truth, false);
  const eval::TrajectoryErrors similar = eval::trajectory_errors(estimate, truth, true);
  std::printf(
      "# seed %d, %.0f m: %.2f %% of the distance after a rigid alignment, mean rotation "
      "error %.2f deg; after a similarity %.2f %%, %.2f deg; %zu tracks rejected\n",
      static_cast<int>(seed), rigid.distance_travelled_m, rigid.translation_error_percent,
      rigid.mean_rotation_error_deg, similar.translation_error_percent,
      similar.mean_rotation_error_deg, filter.rejected().size());
  if (settings.smoothing_window_frames > 0)
    std::printf("# sliding window: %ld solves taken, %ld refused\n", filter.window_solves(),
                filter.window_refusals());
}
