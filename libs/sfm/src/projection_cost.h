#pragma once
// The reprojection residual of a world point seen from a pose, for Ceres: parameter blocks
// cam_from_world as (angle-axis, translation) and the point; analytic Jacobians from the camera
// model and SO(3)'s left Jacobian.

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "omnisfm/camera/catadioptric_camera.h"
#include "so3.h"

namespace omnisfm::sfm {

class ProjectionCost : public ceres::SizedCostFunction<2, 6, 3> {
 public:
  ProjectionCost(const camera::CatadioptricCamera* camera, const Eigen::Vector2d& pixel)
      : camera_(camera), pixel_(pixel) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* pose = parameters[0];
    const double* point = parameters[1];
    Eigen::Vector2d pixel;
    if (!jacobians) {
      double rotated[3];
      ceres::AngleAxisRotatePoint(pose, point, rotated);
      const Eigen::Vector3d X(rotated[0] + pose[3], rotated[1] + pose[4], rotated[2] + pose[5]);
      if (!camera_->project(X, &pixel)) return false;
    } else {
      // X = R(aa) p + t, with dX/daa = -[R p]x J_left(aa) (aa + d turns R by J_left(aa) d on the
      // left) and dX/dp = R.
      const Eigen::Map<const Eigen::Vector3d> aa(pose), p(point), t(pose + 3);
      Eigen::Matrix3d R;
      ceres::AngleAxisToRotationMatrix(pose, ceres::ColumnMajorAdapter3x3(R.data()));
      const Eigen::Vector3d Rp = R * p;
      Eigen::Matrix<double, 2, 3> J_X;
      if (!camera_->project(Rp + t, &pixel, &J_X)) return false;
      if (jacobians[0]) {
        Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_pose(jacobians[0]);
        J_pose << -J_X * so3::skew(Rp) * so3::left_jacobian(aa), J_X;
      }
      if (jacobians[1]) {
        Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J_point(jacobians[1]);
        J_point = J_X * R;
      }
    }
    residuals[0] = pixel.x() - pixel_.x();
    residuals[1] = pixel.y() - pixel_.y();
    return true;
  }

 private:
  const camera::CatadioptricCamera* camera_;
  Eigen::Vector2d pixel_;
};

}  // namespace omnisfm::sfm
