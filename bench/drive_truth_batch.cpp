// What the images alone fix of the drive's orientation, the reference for the online filter's
// (drive_nees; not a benchmark: one run, a line per checkpoint). The batch adjustment over the
// tracks of sim::long_drive, started at the truth and held at the true distance from the first
// camera position to the last (so at the maximum-likelihood estimate nearest the truth, the
// scale fixed), no motion or depth priors: at a few frames, the pose's rotation error and
// standard deviation about each of the camera's axes (z up), as a left perturbation of
// cam_from_world in the first frame's gauge, as drive_nees prints them with axes=1.
//   drive_truth_batch [FRAMES=4000] [SEED=1] [NOISE=0.2]
// 4,000 frames take about 6-7 minutes on one core; 1,000 frames 16 s and 170 MB.

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>

#include "omnisfm/core/pose_vector.h"
#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/sfm/batch_adjustment.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sim/endless_drive.h"

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
  const int frames = argc > 1 ? std::atoi(argv[1]) : 4000;
  const std::uint64_t seed = argc > 2 ? std::strtoull(argv[2], nullptr, 10) : 1;
  const double noise = argc > 3 ? std::atof(argv[3]) : 0.2;
  if (frames < 8) {
    std::fprintf(stderr, "drive_truth_batch: at least 8 frames\n");
    return 2;
  }
  const sim::Dataset d = sim::long_drive(frames, noise, seed);
  std::map<int, Eigen::Vector3d> points;
  for (const core::TrackObservation& o : d.observations) points[o.track] = d.track_points[o.track];
  sfm::BatchSettings settings;
  settings.pixel_sigma = noise > 0 ? noise : 0.2;
  settings.scale_start = false;
  settings.known_distance_m =
      (d.world_from_cam.back().translation() - d.world_from_cam.front().translation()).norm();
  settings.threads = 1;
  const sfm::BatchResult r =
      sfm::batch_adjust(d.camera, d.observations, d.world_from_cam, points, settings);
  std::printf("# seed %d, %d frames: converged %d after %d iterations, %.4f px, %.0f s\n",
              static_cast<int>(seed), frames, r.converged, r.iterations, r.final_rms_px, r.seconds);
  if (!r.usable() || r.cam_from_world_covariances.size() != d.world_from_cam.size()) return 1;
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
        J * r.cam_from_world_covariances[f].topLeftCorner<3, 3>() * J.transpose();
    // As drive_nees takes it, both in the first frame's gauge (the batch holds it at the truth).
    const Eigen::Vector3d e =
        eval::filter_pose_error(d.world_from_cam[f].inverse(),
                                core::isometry_of(r.cam_from_world_parameters[f]))
            .head<3>();
    std::printf("%d  %.3f %.3f %.3f  %.3f %.3f %.3f\n", f, e(0) * kDeg, e(1) * kDeg, e(2) * kDeg,
                std::sqrt(C(0, 0)) * kDeg, std::sqrt(C(1, 1)) * kDeg, std::sqrt(C(2, 2)) * kDeg);
  }
}
