#pragma once
// The batch estimator: Levenberg-Marquardt over all camera poses and 3D points (Ceres, with the
// noncentral projection's analytic Jacobians), started from the online filter's estimates and run
// on its inliers, as the paper does. The first pose is held fixed: with a noncentral camera that
// fixes the gauge, the scale being (weakly) observable through the mirror's size. How weakly is
// measured on every run (BatchResult::scale_sigma_relative); where the images do not fix the
// scale, it is held (BatchResult::scale_source) instead of being left to run away.

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/core/track_observation.h"
#include "omnisfm/sfm/camera_prior.h"

namespace ceres {
class CostFunction;
}

namespace omnisfm::sfm {

// A free scale is kept when the images fix it to within a factor 2 at 3 sigma. The likelihood is
// nearly Gaussian in the inverse scale u (the residuals are nearly linear in it), so the 3-sigma
// interval is u (1 +- 3 r), r the relative standard deviation, i.e. scales from s / (1 + 3 r) to
// s / (1 - 3 r); that lies within [s / 2, 2 s] when 3 r <= 1/2.
constexpr double kMaxFreeScaleSigma = 1.0 / 6;

struct BatchSettings {
  double huber_px = 0;        // a Huber loss of this width; 0 for plain least squares
  int max_iterations = 200;
  bool covariances = true;    // pose and point covariances (dense, for problems of moderate size)
  // With covariances, also each observation's point with its frame's pose: what a point's
  // uncertainty as seen from a camera needs (the scale, shared by both, mostly cancels in it).
  bool point_cam_from_world_covariances = false;
  // Solve with the scene's inverse scale as a parameter of its own first: the scale is weakly
  // observed and the filter's can be far off, which the plain problem takes many iterations to
  // walk. Not with motion sensors' terms that fix the scale themselves (odometry, GPS).
  bool scale_start = true;
  // The tracks' noise, pixels per coordinate: the reprojections' weight against the motion
  // sensors' terms, which are whitened by their own noise. Without them it changes nothing.
  // run_sfm and run_fused_sfm set it to the filter's.
  double pixel_sigma = 1;
  // The true distance between the first and last camera positions, metres, when known (measured
  // with a tape, say); 0 when not. With it the scale is held there rather than taken from the
  // images, unless the motion sensors' terms fix the scale (they then do).
  double known_distance_m = 0;
  // The largest relative standard deviation of the images' scale that is kept free; infinity
  // keeps every scale free (the batch as it was, for studies of the rule).
  double max_free_scale_sigma = kMaxFreeScaleSigma;
  // Threads for the solver and the covariances; 0 for one per core (one for a small problem).
  int threads = 0;
  // A calibration's prior on the camera. With parameters listed (indices into
  // CatadioptricCamera::params(), as a camera file's [omni_camera_covariance] names them), the
  // batch refines them, held to the calibrated values by their covariance (in the parameters'
  // own units), and the camera's other parameters stay as given. The camera is held while the
  // scale is decided, then refined in a last solve, the prior weighed against the pixels at
  // their noise (with the motion sensors' terms pixel_sigma, alone the noise the residuals show
  // by then); where the scale is held at the start's (BatchScale::kHeldAtStart) the camera stays
  // as calibrated, as the mirror's size would take up the scale's error. None listed: the camera
  // is held as given.
  CameraPrior camera_prior;
};

// Where the batch's scale comes from.
enum class BatchScale {
  kFromImages,           // kept free: scale_sigma_relative <= max_free_scale_sigma
  kHeldAtStart,          // the images do not fix it: held at the start's (the filter's) scale
  kHeldAtKnownDistance,  // held at BatchSettings::known_distance_m
  kFromSensors,          // the motion sensors' terms (odometry, GPS) fix it
  kNoTranslation,        // no camera moves from the first: there is no scale
};

struct BatchResult {
  bool converged = false;
  std::string message;
  // A solution to write: the solve converged, or stopped (at its iteration limit) with finite
  // residuals; not one whose residuals could not be evaluated.
  bool usable() const {
    return !world_from_cam.empty() && (converged || std::isfinite(final_rms_px));
  }
  int iterations = 0;
  double initial_rms_px = 0, final_rms_px = 0;  // per coordinate
  // 2 x final cost / degrees of freedom. Alone, the pixels' variance (px^2). With the motion
  // sensors' whitened terms (and the pixels weighed by pixel_sigma), 1 when every stated noise
  // model holds.
  double variance_factor = NAN;
  double seconds = 0;        // in all, covariances included
  double solve_seconds = 0;  // the Levenberg-Marquardt solves alone
  // Ceres's name of the reduced camera system's solver: ITERATIVE_SCHUR when most frames share
  // points, SPARSE_SCHUR when the system is banded (long sequences).
  std::string linear_solver;
  // The scale: where it comes from, and the relative standard deviation of the scale the images
  // alone put on the scene (the marginal standard deviation of the inverse scale at the images'
  // minimum, every other parameter eliminated, scaled by the residuals' variance as the
  // covariances are; with the motion sensors' terms, at their stated noise). Infinite when the
  // images do not fix it at all (its information is singular); NaN when not measured (kFromSensors, kNoTranslation). When the scale
  // was held, this is what made it so (or, with a known distance, what the images would have
  // given), not the uncertainty of the result's scale.
  BatchScale scale_source = BatchScale::kNoTranslation;
  double scale_sigma_relative = NAN;
  // With the camera refined and the scale from the images: scale_sigma_relative is the scale's
  // with the camera refined with it, and this the one with the camera as calibrated, which
  // decided that the images fix the scale. NaN otherwise.
  double scale_sigma_relative_camera_held = NAN;
  // Per frame: the camera's pose in the world, as trajectories leave the estimators.
  std::vector<Eigen::Isometry3d> world_from_cam;
  // The same poses as the batch's parameters hold them, the coordinates of the covariances
  // below: cam_from_world's rotation as an angle-axis vector (its angle may pass pi a little),
  // then its translation (core::isometry_of turns one into its cam_from_world).
  std::vector<core::PoseVector> cam_from_world_parameters;
  // Per track the problem held: a start point none of whose observations could be projected
  // (or whose track was left out) has none.
  std::map<int, Eigen::Vector3d> points;
  // 6x6 per frame (in cam_from_world_parameters' coordinates; frame 0 is fixed: zero) and 3x3 per
  // point, when asked for and computable; with a held scale, the scale held.
  std::vector<Eigen::Matrix<double, 6, 6>> cam_from_world_covariances;
  // The covariance of frame f's pose with frame f + 1's (rows f, columns f + 1), per frame but the
  // last; with cam_from_world_covariances, what relative poses' uncertainties need.
  std::vector<Eigen::Matrix<double, 6, 6>> consecutive_cam_from_world_covariances;
  std::map<int, Eigen::Matrix3d> point_covariances;
  // With BatchSettings::point_cam_from_world_covariances: keyed (track, frame), per observation
  // used whose frame is not the fixed first, the covariance of the point (rows) with the frame's
  // pose parameters (columns, as cam_from_world_covariances').
  std::map<std::pair<int, int>, Eigen::Matrix<double, 3, 6>> point_cam_from_world_covariances;
  // With BatchSettings::camera_prior, whether the camera was refined: not where the scale was
  // held at the start's or nothing moved, nor when the refining solve failed (the result is then
  // the one before it). Refined, the camera's params() (all of them) and, with the covariances,
  // the covariance of the refined ones in camera_prior's order.
  bool camera_refined = false;
  Eigen::VectorXd camera_params;
  Eigen::MatrixXd camera_covariance;
};

// observations: every observation to use (outliers already removed); start_world_from_cam: a
// start for every frame; points: a start for every track observed. A known_distance_m that is
// negative or not finite fails the batch (converged false, no estimate, message saying why).
BatchResult batch_adjust(const camera::CatadioptricCamera& camera,
                         const std::vector<core::TrackObservation>& observations,
                         const std::vector<Eigen::Isometry3d>& start_world_from_cam,
                         const std::map<int, Eigen::Vector3d>& points,
                         const BatchSettings& settings);

// The camera the batch optimises with: `camera` with its mirror's valid patch widened by a tenth
// of its width each way, where the profile allows. A step that carries a point's reflection just
// past the rim then keeps a finite, smooth residual instead of being refused, and a point that
// converges there (within its noise) still fits. Residuals of the batch's result are judged with it.
camera::CatadioptricCamera batch_camera(const camera::CatadioptricCamera& camera);

// The batch's reprojection residual of a world point from a pose (angle-axis, translation), with
// analytic Jacobians; the caller owns it. For benchmarks and other problems built on the same
// residual.
ceres::CostFunction* make_projection_cost(const camera::CatadioptricCamera* camera,
                                          const Eigen::Vector2d& pixel);

}  // namespace omnisfm::sfm
