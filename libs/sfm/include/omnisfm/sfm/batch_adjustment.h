#pragma once
// The batch estimator: Levenberg-Marquardt over all camera poses and 3D points (Ceres, with the
// noncentral projection's analytic Jacobians), started from the online filter's estimates and run
// on its inliers, as the paper does. The first pose is held fixed: with a noncentral camera that
// fixes the gauge, the scale being (weakly) observable through the mirror's size.

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tracks_file.h"

namespace ceres {
class CostFunction;
}

namespace omnisfm::sfm {

struct BatchSettings {
  double huber_px = 0;        // a Huber loss of this width; 0 for plain least squares
  int max_iterations = 200;
  bool covariances = true;    // pose and point covariances (dense, for problems of moderate size)
  // Solve with the scene's inverse scale as a parameter of its own first: the scale is weakly
  // observed and the filter's can be far off, which the plain problem takes many iterations to
  // walk. Not with the motion sensors' terms, which fix the scale themselves.
  bool scale_start = true;
  // The tracks' noise, pixels per coordinate: the reprojections' weight against the motion
  // sensors' terms, which are whitened by their own noise. Without them it changes nothing.
  double pixel_sigma = 1;
};

struct BatchResult {
  bool converged = false;
  std::string message;
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
  std::vector<Eigen::Isometry3d> cam_from_world;  // per frame
  std::map<int, Eigen::Vector3d> points;           // per track
  // 6x6 per frame (rotation as angle-axis, then translation; frame 0 is fixed: zero) and 3x3 per
  // point, when asked for and computable.
  std::vector<Eigen::Matrix<double, 6, 6>> pose_covariances;
  std::map<int, Eigen::Matrix3d> point_covariances;
};

// observations: every observation to use (outliers already removed); cam_from_world: a start for
// every frame; points: a start for every track observed.
BatchResult batch_adjust(const camera::CatadioptricCamera& camera,
                         const std::vector<io::TrackObservation>& observations,
                         const std::vector<Eigen::Isometry3d>& cam_from_world,
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
