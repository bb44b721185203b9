#pragma once
// How far the calibrated parameters' uncertainty moves projections, over the image. At each grid
// pixel, the point at `distance_m` along the pixel's reflected ray (frame C) is projected, and the
// 2x2 covariance of that projection, J Sigma J^T, gives the 1-sigma uncertainty along its worst
// direction, sqrt(largest eigenvalue), as mrcal reports it.
//
// Which point is held fixed matters. The calibration fixes the rig's pixels-to-rays mapping only
// up to a rigid motion of the whole rig, which the views' poses absorb; so a point held fixed in
// frame C moves by that unobservable motion too. As mrcal does, the point is held fixed relative
// to the calibration objects instead: q = project(mean over views v of T_v X_v), with X_v the
// point in view v's object frame, and J the derivative of q with respect to the camera parameters
// and all the views' poses, Sigma their joint covariance.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/calib/calibration_problem.h"

namespace omnisfm::calib {

struct UncertaintyMap {
  double distance_m = 0;
  int step_px = 0;                 // grid spacing; samples at (i * step_px, j * step_px)
  int columns = 0, rows = 0;
  std::vector<double> sigma_px;    // row-major; NaN where the pixel sees no mirror
  double sigma_at(int column, int row) const { return sigma_px[row * columns + column]; }
};

// `parameters` names the estimated parameters (CatadioptricCamera::param_names()), in the order of
// the first rows of `joint_covariance`, which continues with the views' poses, as
// CalibrationReport holds it; `views` carries those poses. Throws std::invalid_argument for an
// unknown name or a size mismatch.
UncertaintyMap projection_uncertainty(const camera::CatadioptricCamera& camera,
                                      const std::vector<std::string>& parameters,
                                      const std::vector<CalibrationView>& views,
                                      const Eigen::MatrixXd& joint_covariance, double distance_m,
                                      int step_px);

// The 2x2 covariance of the projection of one point X_C (frame C, at the solution), held fixed
// relative to the calibration objects as above. False where X_C does not project.
bool projection_covariance(const camera::CatadioptricCamera& camera,
                           const std::vector<std::string>& parameters,
                           const std::vector<CalibrationView>& views,
                           const Eigen::MatrixXd& joint_covariance, const Eigen::Vector3d& X_C,
                           Eigen::Matrix2d* covariance);

// The same with the point fixed in frame C: J is the derivative with respect to the camera
// parameters alone, Sigma their covariance. Larger, since it counts the rig's unobservable motion.
UncertaintyMap projection_uncertainty_in_camera_frame(const camera::CatadioptricCamera& camera,
                                                      const std::vector<std::string>& parameters,
                                                      const Eigen::MatrixXd& covariance,
                                                      double distance_m, int step_px);

}  // namespace omnisfm::calib
