// What the images alone fix of the drive's orientation, the reference for the online filter's
// (drive_nees; not a benchmark: one run, a line per checkpoint). The batch adjustment over the
// tracks of sim::long_drive, started at the truth and held at the true distance from the first
// camera position to the last (so at the maximum-likelihood estimate nearest the truth, the
// scale fixed), no motion or depth priors: at a few frames, the pose's rotation error and
// standard deviation about each of the camera's axes (z up), as a left perturbation of
// cam_from_world in the first frame's gauge, as drive_nees prints them with axes=1.
//   drive_truth_batch [FRAMES=4000] [SEED=1] [NOISE=0.2] [SIGMAS=1] [START=0] [ITERATIONS=200]
//   [HOLD=1]
// or each by name, anywhere: frames=20000 seed=2 sigmas=0 hold=0 (lower case).
// HOLD 0 leaves the scale free (every scale kept, however weakly the images fix it); 2 as the
// batch decides by default (held at the start's where the images fix it to worse than a factor 2).
// START 1 starts the batch at the online filter's estimate instead (vision alone, its settings'
// defaults, as drive_nees runs it with SENSORS 0), brought to the first pose and the true distance:
// whether the minimum the truth's start finds is the one a start the truth does not know reaches.
// SIGMAS 0 leaves the covariances out (they are dense: beyond about 5,000 frames they do not fit).
// At the end, the mean rotation error after a similarity alignment, as drive_nees prints it.
// 4,000 frames take about 6-7 minutes on one core; 1,000 frames 16 s and 170 MB.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/core/pose_vector.h"
#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/eval/filter_run.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sim/endless_drive.h"
#include "setting_assignment.h"

namespace {

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, v / angle).toRotationMatrix();
}

Eigen::Vector3d log_so3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace omnisfm;
  sfm::use_one_blas_thread();
  // Positional, or by name anywhere (frames=4000 seed=2 ...; a name overrides its position).
  double frames_value = 4000, seed_value = 1, noise = 0.2, sigmas_value = 1, start_value = 0,
         iterations_value = 200, hold_value = 1;
  const bench::Setters settable = {
      {"frames", [&](double v) { frames_value = v; }},
      {"seed", [&](double v) { seed_value = v; }},
      {"noise", [&](double v) { noise = v; }},
      {"sigmas", [&](double v) { sigmas_value = v; }},
      {"start", [&](double v) { start_value = v; }},
      {"iterations", [&](double v) { iterations_value = v; }},
      {"hold", [&](double v) { hold_value = v; }},
  };
  double* const by_position[] = {&frames_value, &seed_value,       &noise,     &sigmas_value,
                                 &start_value,  &iterations_value, &hold_value};
  std::vector<std::string> assignments;
  size_t position = 0;
  for (int k = 1; k < argc; ++k) {
    if (std::strchr(argv[k], '=')) {
      assignments.push_back(argv[k]);
    } else if (position < std::size(by_position)) {
      if (!bench::parse_number(argv[k], by_position[position++])) {
        std::fprintf(stderr, "drive_truth_batch: %s is not a number\n", argv[k]);
        return 2;
      }
    } else {
      std::fprintf(stderr, "drive_truth_batch: too many arguments at %s\n", argv[k]);
      return 2;
    }
  }
  for (const std::string& assignment : assignments)
    if (!bench::apply_assignment(assignment, settable)) {
      std::fprintf(stderr, "drive_truth_batch: unknown setting, or not a number: %s\n",
                   assignment.c_str());
      return 2;
    }
  // Whole numbers within their types' ranges (a seed of 2^53 or more would lose digits).
  const auto whole = [](double v, double high) {
    return v == std::floor(v) && v >= 0 && v <= high;
  };
  if (!whole(frames_value, 1e8) || !whole(seed_value, 9007199254740992.0) ||
      !whole(iterations_value, 1e8) || !whole(hold_value, 2)) {
    std::fprintf(stderr,
                 "drive_truth_batch: frames, seed, iterations and hold are whole numbers "
                 "of 0 or more (hold at most 2)\n");
    return 2;
  }
  const int frames = static_cast<int>(frames_value);
  const auto seed = static_cast<std::uint64_t>(seed_value);
  const bool sigmas = sigmas_value != 0;
  const bool from_filter = start_value != 0;
  const int iterations = static_cast<int>(iterations_value);
  const int hold = static_cast<int>(hold_value);
  const bool hold_distance = hold == 1;
  if (frames < 8) {
    std::fprintf(stderr, "drive_truth_batch: at least 8 frames\n");
    return 2;
  }
  const sim::Dataset d = sim::long_drive(frames, noise, seed);
  std::map<int, Eigen::Vector3d> points;
  std::vector<Eigen::Isometry3d> start = d.world_from_cam;
  std::vector<core::TrackObservation> observations = d.observations;
  if (from_filter) {
    sfm::FilterSettings filter_settings;
    sfm::OnlineFilter filter(d.camera, filter_settings);
    filter.on_point_ended([&](int track, const Eigen::Vector3d& p) { points[track] = p; });
    std::vector<Eigen::Isometry3d> first_from_cam;
    eval::run_filter(d, nullptr, filter_settings, &filter,
                     [&](int) { first_from_cam.push_back(filter.cam_from_world().inverse()); });
    for (const auto& [track, p] : filter.points()) points[track] = p;
    // The filter's map in the first camera's frame at its own scale: to the truth's first pose,
    // and where the distance is held, to it.
    const double scale =
        hold_distance
            ? (d.world_from_cam.back().translation() - d.world_from_cam.front().translation())
                      .norm() /
                  (first_from_cam.back().translation() - first_from_cam.front().translation())
                      .norm()
            : 1.0;
    const auto to_world = [&](const Eigen::Vector3d& p) -> Eigen::Vector3d {
      return d.world_from_cam[0] * (scale * p);
    };
    for (size_t f = 0; f < start.size(); ++f) {
      start[f] = first_from_cam[f];
      start[f].translation() *= scale;
      start[f] = d.world_from_cam[0] * start[f];
    }
    for (auto& [track, p] : points) p = to_world(p);
    observations.erase(
        std::remove_if(observations.begin(), observations.end(),
                       [&](const core::TrackObservation& o) { return !points.count(o.track); }),
        observations.end());
    std::printf(
        "# started at the filter's estimate (its map %.3f times the truth's), %zu points\n",
        (first_from_cam.back().translation() - first_from_cam.front().translation()).norm() /
            (d.world_from_cam.back().translation() - d.world_from_cam.front().translation()).norm(),
        points.size());
  } else {
    for (const core::TrackObservation& o : observations) points[o.track] = d.track_points[o.track];
  }
  sfm::BatchSettings settings;
  settings.pixel_sigma = noise > 0 ? noise : 0.2;
  settings.scale_start = from_filter && !hold_distance;
  const double distance =
      (d.world_from_cam.back().translation() - d.world_from_cam.front().translation()).norm();
  if (hold_distance)
    settings.known_distance_m = distance;
  else if (hold == 0)
    settings.max_free_scale_sigma = INFINITY;
  settings.threads = 1;
  settings.covariances = sigmas;
  settings.max_iterations = iterations;
  const sfm::BatchResult r = sfm::batch_adjust(d.camera, observations, start, points, settings);
  std::printf("# seed %d, %d frames: converged %d after %d iterations, %.4f px, %.0f s\n",
              static_cast<int>(seed), frames, r.converged, r.iterations, r.final_rms_px, r.seconds);
  if (!r.usable() || (sigmas && r.cam_from_world_covariances.size() != d.world_from_cam.size()))
    return 1;
  std::printf(
      "# scale %.3f of the truth's (%s), the images' relative sigma %.3f\n",
      (r.world_from_cam.back().translation() - r.world_from_cam.front().translation()).norm() /
          distance,
      r.scale_source == sfm::BatchScale::kFromImages ? "the images'" : "held",
      r.scale_sigma_relative);
  std::printf("# frame  error about x y z (deg)  sigma about x y z (deg)\n");
  constexpr double kDeg = 180 / M_PI;
  for (const int f : {frames / 8, frames / 4, frames / 2, frames - 1}) {
    const Eigen::Vector3d aa = r.cam_from_world_parameters[f].head<3>();
    const Eigen::Matrix3d R = exp_so3(aa);
    // The covariance is in the angle-axis parameters; the left perturbation's, per column.
    Eigen::Matrix3d J;
    for (int k = 0; k < 3; ++k) {
      constexpr double kStep = 1e-7;
      J.col(k) = log_so3(exp_so3(aa + kStep * Eigen::Vector3d::Unit(k)) * R.transpose()) / kStep;
    }
    const Eigen::Matrix3d C =
        sigmas ? Eigen::Matrix3d(J * r.cam_from_world_covariances[f].topLeftCorner<3, 3>() *
                                 J.transpose())
               : Eigen::Matrix3d::Constant(NAN);
    // As drive_nees takes it, both in the first frame's gauge (the batch holds it at the truth).
    const Eigen::Vector3d e =
        eval::filter_pose_error(d.world_from_cam[f].inverse(),
                                core::isometry_of(r.cam_from_world_parameters[f]))
            .head<3>();
    std::printf("%d  %.3f %.3f %.3f  %.3f %.3f %.3f\n", f, e(0) * kDeg, e(1) * kDeg, e(2) * kDeg,
                std::sqrt(C(0, 0)) * kDeg, std::sqrt(C(1, 1)) * kDeg, std::sqrt(C(2, 2)) * kDeg);
  }
  std::vector<Eigen::Isometry3d> estimate;
  for (const core::PoseVector& p : r.cam_from_world_parameters)
    estimate.push_back(core::isometry_of(p).inverse());
  const eval::TrajectoryErrors similar = eval::trajectory_errors(estimate, d.world_from_cam, true);
  std::printf("# after a similarity %.2f %% of %.0f m, mean rotation error %.2f deg\n",
              similar.translation_error_percent, similar.distance_travelled_m,
              similar.mean_rotation_error_deg);
}
