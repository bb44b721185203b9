#pragma once
// The best central mrcal lens model for a catadioptric camera, so that tools that know only
// central cameras (mrcal-reproject-image, mrcal-show-projection-diff) work with the rig.
//
// A noncentral camera has no exact central model: its reflected rays do not meet in one point.
// For pixels on a grid over the valid image, the point X = origin + distance * direction on each
// reflected ray is fitted: the model's intrinsics minimise the pixel reprojection error
//   q_mrcal(R X + t; intrinsics) - pixel
// with mrcal's own projection and gradients, in Ceres. At the chosen distance the error is the
// model's lack of flexibility only; at other distances the rays' offsets from the model's centre
// add the noncentral error.
//
// The model's frame (mrcal's camera frame, with frame C as mrcal's reference, so that
// X_model = R X_C + t are the extrinsics rt_cam_ref):
// - origin: the point nearest to all the sampled rays (least squares), which makes the error at
//   other distances as small as one centre allows;
// - z along the mirror frame's -z: the rays leave the mirror around that axis, sideways and back
//   toward the camera, so the field (over 180 degrees for the equiangular rig) is centred;
// - x along the mirror frame's x, y along its -y (a half turn about the mirror's x axis).
// A mirror shows a mirrored image, which no rotation undoes: the fitted fy is negative.
//
// Lens model: LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=N_Ny=N_fov_x_deg=F with N control
// points on both axes (the field is round) and F twice the widest angle of a sampled ray from the
// model's z axis, plus a margin: the spline's domain ends at the stereographic radius
// u = 2 tan(F/4), and a ray at angle a from z has u = 2 tan(a/2). The core (fx fy cx cy) is the
// plain stereographic fit and the spline the correction to it; a paraboloid seen by a telecentric
// lens is exactly stereographic, and its spline stays flat.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/cameramodel_file.h"

namespace omnisfm::calib {

// A pixel and its reflected ray in frame C: origin on the mirror, unit direction.
struct PixelRay {
  Eigen::Vector2d pixel;
  Eigen::Vector3d origin, direction;
};

// The pixels of a square grid with spacing `step_px`, centred on the image, whose reflection is
// valid, with their rays.
std::vector<PixelRay> valid_pixel_rays(const camera::CatadioptricCamera& camera, double step_px);

// The fitted model: a .cameramodel's contents (its valid_intrinsics_region the convex outline of
// the fitted pixels, which takes in the camera's own reflection at the centre, which no single
// outline can leave out), and its projection.
struct CentralMrcalModel : io::MrcalCameraModel {
  // The pixel of X (frame C); false where mrcal gives no finite pixel.
  bool project(const Eigen::Vector3d& X_C, Eigen::Vector2d* pixel) const;
  // The pixel of the direction `direction` (frame C) at infinite distance.
  bool project_direction(const Eigen::Vector3d& direction_C, Eigen::Vector2d* pixel) const;
};

struct CentralFitSettings {
  double distance_m = 1;  // from the mirror along each ray; finite, > 0
  int knots = 16;         // spline control points per axis, 4 to 100
};

// Throws std::invalid_argument for a setting out of range or rays that allow no fit (too few, a
// field too wide for a stereographic model), std::runtime_error when the solver fails.
CentralMrcalModel fit_central_mrcal_model(const camera::CatadioptricCamera& camera,
                                          const std::vector<PixelRay>& rays,
                                          const CentralFitSettings& settings);

struct ReprojectionError {
  double distance_m = 0;  // infinity: the rays' directions
  int num_points = 0;     // rays whose point projected to a finite pixel
  int num_failed = 0;     // rays whose point did not
  double rms_px = 0, worst_px = 0;
};

// The model's reprojection error over `rays` for the points at `distance_m` along them.
ReprojectionError reprojection_error(const CentralMrcalModel& model,
                                     const std::vector<PixelRay>& rays, double distance_m);

}  // namespace omnisfm::calib
