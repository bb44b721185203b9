#pragma once
// The reprojection residual of a world point seen from a pose, for Ceres: parameter blocks
// cam_from_world as (angle-axis, translation) and the point (and, scaled, the scene's inverse
// scale); analytic Jacobians from the camera model and SO(3)'s left Jacobian.

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "omnisfm/camera/catadioptric_camera.h"
#include "so3.h"

namespace omnisfm::sfm {

// pixel - observed for the camera-frame point X = (R(aa) p + t) / u, with the Jacobians asked
// for (row-major; null when not; J_params with respect to the camera's params()).
// dX/daa = -[R p]x J_left(aa) / u (aa + d turns R by J_left(aa) d on the left), dX/dt = I / u,
// dX/dp = R / u, dX/du = -X / u.
inline bool evaluate_projection(const camera::CatadioptricCamera& camera,
                                const Eigen::Vector2d& observed, const double* pose,
                                const double* point, double u, double* residuals,
                                double* J_pose_out, double* J_point_out, double* J_u_out,
                                camera::ParamsJacobian* J_params = nullptr) {
  Eigen::Vector2d pixel;
  if (!J_pose_out && !J_point_out && !J_u_out && !J_params) {
    double rotated[3];
    ceres::AngleAxisRotatePoint(pose, point, rotated);
    const Eigen::Vector3d X(rotated[0] + pose[3], rotated[1] + pose[4], rotated[2] + pose[5]);
    if (!camera.project(X / u, &pixel)) return false;
  } else {
    const Eigen::Map<const Eigen::Vector3d> aa(pose), p(point), t(pose + 3);
    Eigen::Matrix3d R;
    ceres::AngleAxisToRotationMatrix(pose, ceres::ColumnMajorAdapter3x3(R.data()));
    const Eigen::Vector3d Rp = R * p;
    const Eigen::Vector3d X = (Rp + t) / u;
    Eigen::Matrix<double, 2, 3> J_X;
    if (!camera.project(X, &pixel, &J_X, J_params)) return false;
    if (u != 1) J_X /= u;
    if (J_pose_out) {
      Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_pose(J_pose_out);
      J_pose << -J_X * so3::skew(Rp) * so3::left_jacobian(aa), J_X;
    }
    if (J_point_out) Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>{J_point_out} = J_X * R;
    if (J_u_out) Eigen::Map<Eigen::Vector2d>{J_u_out} = -J_X * X;
  }
  residuals[0] = pixel.x() - observed.x();
  residuals[1] = pixel.y() - observed.y();
  return true;
}

class ProjectionCost : public ceres::SizedCostFunction<2, 6, 3> {
 public:
  ProjectionCost(const camera::CatadioptricCamera* camera, const Eigen::Vector2d& pixel)
      : camera_(camera), pixel_(pixel) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    return evaluate_projection(*camera_, pixel_, parameters[0], parameters[1], 1, residuals,
                               jacobians ? jacobians[0] : nullptr,
                               jacobians ? jacobians[1] : nullptr, nullptr);
  }

 private:
  const camera::CatadioptricCamera* camera_;
  Eigen::Vector2d pixel_;
};

// The same residual with the scene's inverse scale u as a third parameter block: the camera-frame
// point is (R p + t) / u. The residuals are nearly linear in u (scaling the scene by s is scaling
// the mirror by 1/s), where along the translations and points they are not.
class ScaledProjectionCost : public ceres::SizedCostFunction<2, 6, 3, 1> {
 public:
  ScaledProjectionCost(const camera::CatadioptricCamera* camera, const Eigen::Vector2d& pixel)
      : camera_(camera), pixel_(pixel) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!(parameters[2][0] > 0)) return false;  // the scene at or past infinity
    return evaluate_projection(*camera_, pixel_, parameters[0], parameters[1], parameters[2][0],
                               residuals, jacobians ? jacobians[0] : nullptr,
                               jacobians ? jacobians[1] : nullptr,
                               jacobians ? jacobians[2] : nullptr);
  }

 private:
  const camera::CatadioptricCamera* camera_;
  Eigen::Vector2d pixel_;
};

}  // namespace omnisfm::sfm
