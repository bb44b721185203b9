#include "omnisfm/calib/projection_uncertainty.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "pose_jacobian.h"

namespace omnisfm::calib {
namespace {

std::vector<int> parameter_columns(const camera::CatadioptricCamera& camera,
                                   const std::vector<std::string>& parameters) {
  const std::vector<std::string> names = camera.param_names();
  std::vector<int> columns;
  for (const std::string& name : parameters) {
    const auto found = std::find(names.begin(), names.end(), name);
    if (found == names.end())
      throw std::invalid_argument("projection_uncertainty: the camera has no parameter " + name);
    columns.push_back(static_cast<int>(found - names.begin()));
  }
  return columns;
}

double worst_direction_sigma(const Eigen::Matrix2d& pixel_covariance) {
  const double largest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(pixel_covariance, Eigen::EigenvaluesOnly)
          .eigenvalues()[1];
  return std::sqrt(std::max(0.0, largest));
}

// Fills the map from `sigma_of(point in frame C)`, which returns false where it cannot project.
template <typename SigmaOf>
UncertaintyMap map_over_image(const camera::CatadioptricCamera& camera, double distance_m,
                              int step_px, SigmaOf sigma_of) {
  if (step_px <= 0 || !(distance_m > 0))
    throw std::invalid_argument("projection_uncertainty: need step_px > 0 and distance_m > 0");
  UncertaintyMap map;
  map.distance_m = distance_m;
  map.step_px = step_px;
  map.columns = (camera.image_width() - 1) / step_px + 1;
  map.rows = (camera.image_height() - 1) / step_px + 1;
  map.sigma_px.assign(map.columns * map.rows, std::numeric_limits<double>::quiet_NaN());
  for (int row = 0; row < map.rows; ++row) {
    for (int column = 0; column < map.columns; ++column) {
      Eigen::Vector3d origin, direction;
      if (!camera.unproject(Eigen::Vector2d(column * step_px, row * step_px), &origin, &direction))
        continue;
      double sigma = 0;
      if (sigma_of(Eigen::Vector3d(origin + distance_m * direction), &sigma))
        map.sigma_px[row * map.columns + column] = sigma;
    }
  }
  return map;
}

}  // namespace

bool projection_covariance(const camera::CatadioptricCamera& camera,
                           const std::vector<std::string>& parameters,
                           const std::vector<CalibrationView>& views,
                           const Eigen::MatrixXd& joint_covariance, const Eigen::Vector3d& X_C,
                           Eigen::Matrix2d* covariance) {
  const std::vector<int> columns = parameter_columns(camera, parameters);
  const int m = static_cast<int>(columns.size());
  const int num_views = static_cast<int>(views.size());
  const int n = m + 6 * num_views;
  if (num_views == 0 || joint_covariance.rows() != n || joint_covariance.cols() != n)
    throw std::invalid_argument("projection_uncertainty: the covariance does not match the views");
  // The point in each view's object frame, mapped back through the poses and averaged.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_mean_poses(3, 6 * num_views);
  for (int v = 0; v < num_views; ++v) {
    const Eigen::Vector3d X_object = views[v].cam_from_object.inverse() * X_C;
    const Eigen::Matrix<double, 6, 1> pose = core::pose_vector_of(views[v].cam_from_object);
    Eigen::Matrix<double, 3, 6> J_pose;
    mean += transform_point(pose.data(), X_object, &J_pose) / num_views;
    J_mean_poses.middleCols<6>(6 * v) = J_pose / num_views;
  }
  Eigen::Vector2d q;
  Eigen::Matrix<double, 2, 3> J_X;
  camera::ParamsJacobian J_params;
  if (!camera.project(mean, &q, &J_X, &J_params)) return false;
  Eigen::Matrix<double, 2, Eigen::Dynamic> J(2, n);
  for (int k = 0; k < m; ++k) J.col(k) = J_params.col(columns[k]);
  J.rightCols(6 * num_views) = J_X * J_mean_poses;
  *covariance = J * joint_covariance * J.transpose();
  return true;
}

UncertaintyMap projection_uncertainty(const camera::CatadioptricCamera& camera,
                                      const std::vector<std::string>& parameters,
                                      const std::vector<CalibrationView>& views,
                                      const Eigen::MatrixXd& joint_covariance, double distance_m,
                                      int step_px) {
  return map_over_image(camera, distance_m, step_px, [&](const Eigen::Vector3d& X_C, double* sigma) {
    Eigen::Matrix2d covariance;
    if (!projection_covariance(camera, parameters, views, joint_covariance, X_C, &covariance))
      return false;
    *sigma = worst_direction_sigma(covariance);
    return true;
  });
}

UncertaintyMap projection_uncertainty_in_camera_frame(const camera::CatadioptricCamera& camera,
                                                      const std::vector<std::string>& parameters,
                                                      const Eigen::MatrixXd& covariance,
                                                      double distance_m, int step_px) {
  const std::vector<int> columns = parameter_columns(camera, parameters);
  const int m = static_cast<int>(columns.size());
  if (covariance.rows() != m || covariance.cols() != m)
    throw std::invalid_argument("projection_uncertainty: the covariance does not match the names");
  camera::ParamsJacobian J_params;
  Eigen::Matrix<double, 2, Eigen::Dynamic> J(2, m);
  return map_over_image(camera, distance_m, step_px, [&](const Eigen::Vector3d& X_C, double* sigma) {
    Eigen::Vector2d q;
    if (!camera.project(X_C, &q, nullptr, &J_params)) return false;
    for (int k = 0; k < m; ++k) J.col(k) = J_params.col(columns[k]);
    *sigma = worst_direction_sigma(J * covariance * J.transpose());
    return true;
  });
}

}  // namespace omnisfm::calib
