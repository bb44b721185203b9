#pragma once
// The reprojection residual of a world point seen from a pose, for Ceres: parameter blocks
// cam_from_world as (angle-axis, translation) and the point; analytic Jacobians from the camera
// model, the rotation's from Jets.

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include "omnisfm/camera/catadioptric_camera.h"

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
      // X = R(aa) p + t: derivatives with respect to aa and p from one 6-dimensional Jet pass.
      using Jet = ceres::Jet<double, 6>;
      Jet aa[3], p[3], rotated[3];
      for (int i = 0; i < 3; ++i) {
        aa[i] = Jet(pose[i], i);
        p[i] = Jet(point[i], 3 + i);
      }
      ceres::AngleAxisRotatePoint(aa, p, rotated);
      Eigen::Vector3d X;
      Eigen::Matrix<double, 3, 6> J_rot_point;
      for (int r = 0; r < 3; ++r) {
        X[r] = rotated[r].a + pose[3 + r];
        J_rot_point.row(r) = rotated[r].v.transpose();
      }
      Eigen::Matrix<double, 2, 3> J_X;
      if (!camera_->project(X, &pixel, &J_X)) return false;
      if (jacobians[0]) {
        Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_pose(jacobians[0]);
        J_pose << J_X * J_rot_point.leftCols<3>(), J_X;
      }
      if (jacobians[1]) {
        Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> J_point(jacobians[1]);
        J_point = J_X * J_rot_point.rightCols<3>();
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
