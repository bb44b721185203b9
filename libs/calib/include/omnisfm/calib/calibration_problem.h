#pragma once
// Calibration of a catadioptric camera from views of known 3D points: surveyed targets (the
// paper's method: the mirror-to-camera transform plus the camera's pose) or checkerboards (every
// board's pose plus any chosen camera parameters). One least-squares problem serves both: per view
// a 6-DOF pose cam_from_object, shared camera parameters, residuals in pixels.
//
// The solve is Levenberg-Marquardt (Ceres) with the camera model's analytic Jacobians, followed by
// rounds of outlier rejection; the parameter covariance is (J^T J)^-1 scaled by the residual
// variance, the poses marginalised, as mrcal reports it.

#include <Eigen/Geometry>
#include <functional>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::calib {

struct CalibrationView {
  std::string name;                     // image name, for reports
  std::vector<Eigen::Vector3d> points;  // in the object's frame (the room, the board)
  std::vector<Eigen::Vector2d> pixels;  // observed, one per point
  std::vector<int> point_ids;           // optional, for reports: target ids, board indices
  Eigen::Isometry3d cam_from_object = Eigen::Isometry3d::Identity();  // initial, then solved
};

struct CalibrationSettings {
  // Which camera parameters (CatadioptricCamera::params() order) are estimated.
  std::vector<bool> estimate;
  // A residual above this many times the residual sigma is an outlier (as mrcal's cut).
  double outlier_threshold_sigma = 4.0;
  // Rounds of rejection, each followed by a new solve; 0 solves once and rejects nothing.
  int max_outlier_rounds = 5;
  int max_iterations = 200;
  // When > 0, a Cauchy loss of this scale (pixels) instead of squares: for rough starting
  // guesses, where a few far-off residuals would otherwise pull the whole solve.
  double cauchy_scale_px = 0;
  // Called after every solver iteration with the iteration count and the RMS residual (pixels
  // per coordinate) so far; may be empty.
  std::function<void(int iteration, double rms_px)> progress;
  // Threads for the solver; 0 for one under 5,000 residuals (the same digits on every run), else
  // one per core (core::solver_threads).
  int threads = 0;
};

struct ObservationResidual {
  int view = 0, index = 0;
  Eigen::Vector2d residual{0, 0};  // projected - observed, pixels
  bool outlier = false;
};

struct CalibrationReport {
  bool converged = false;
  std::string message;  // why the solver stopped, or what is wrong
  int iterations = 0;
  int num_observations = 0, num_outliers = 0;
  double rms_px = 0;                   // over inliers' coordinates, as mrcal reports it
  double worst_px = 0;                 // largest inlier residual's length
  std::vector<double> view_rms_px;     // per view, over its inliers' coordinates
  std::vector<ObservationResidual> residuals;
  std::vector<std::string> estimated_names;
  Eigen::MatrixXd covariance;          // of the estimated parameters
  // Of all unknowns: the estimated parameters, then each view's pose as the solver holds it
  // (angle-axis, then translation, of cam_from_object).
  Eigen::MatrixXd joint_covariance;
  double residual_sigma_px = 0;        // sqrt(SSR / (N - P))
};

// Names of the parameter groups a user can estimate: mirror-pose, mirror-shape, intrinsics (the
// inner camera's focal lengths and centre), distortion (the rest of the inner camera's), all.
// Throws std::invalid_argument naming an unknown group.
std::vector<bool> estimate_mask(const camera::CatadioptricCamera& camera,
                                const std::vector<std::string>& groups);

// Solves for the views' poses and the estimated camera parameters, starting from the values given.
// Never throws for a bad solve: the report says whether it converged and why not.
// Throws std::invalid_argument when there are fewer residuals than unknowns.
CalibrationReport calibrate(camera::CatadioptricCamera* camera, std::vector<CalibrationView>* views,
                            const CalibrationSettings& settings);

}  // namespace omnisfm::calib
