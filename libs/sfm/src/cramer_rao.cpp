#include "omnisfm/core/pose_vector.h"
#include "omnisfm/sfm/cramer_rao.h"

#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

#include "projection_cost.h"

namespace omnisfm::sfm {

PositionBound camera_position_bound(
    const camera::CatadioptricCamera& camera, const std::vector<core::TrackObservation>& observations,
    const std::vector<Eigen::Isometry3d>& world_from_cam,
    const std::map<int, Eigen::Vector3d>& points, double pixel_sigma) {
  const int frames = static_cast<int>(world_from_cam.size());
  std::map<int, int> point_index;
  for (const auto& [track, X] : points) point_index.emplace(track, static_cast<int>(point_index.size()));
  // Unknowns: poses 1.. (angle-axis, translation, as the batch holds them), then the points.
  const int n = 6 * (frames - 1) + 3 * static_cast<int>(points.size());
  std::vector<core::PoseVector> poses(frames);
  for (int f = 0; f < frames; ++f) poses[f] = core::pose_vector_of(world_from_cam[f].inverse());
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(n, n);
  for (const auto& o : observations) {
    const auto point = points.find(o.track);
    if (point == points.end() || o.frame < 0 || o.frame >= frames) continue;
    const ProjectionCost cost(&camera, Eigen::Vector2d::Zero());
    double residual[2], J_pose[12], J_point[6];
    double* jacobians[2] = {J_pose, J_point};
    const double* parameters[2] = {poses[o.frame].data(), point->second.data()};
    if (!cost.Evaluate(parameters, residual, jacobians)) continue;
    const int p = 6 * (frames - 1) + 3 * point_index.at(o.track);
    const Eigen::Map<Eigen::Matrix<double, 2, 3, Eigen::RowMajor>> Jx(J_point);
    information.block<3, 3>(p, p) += Jx.transpose() * Jx;
    if (o.frame > 0) {
      const int c = 6 * (o.frame - 1);
      const Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> Jc(J_pose);
      information.block<6, 6>(c, c) += Jc.transpose() * Jc;
      information.block<6, 3>(c, p) += Jc.transpose() * Jx;
      information.block<3, 6>(p, c) += Jx.transpose() * Jc;
    }
  }
  information /= pixel_sigma * pixel_sigma;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(information);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0))
    throw std::invalid_argument("the Fisher information is singular: the problem is not observable");
  const Eigen::MatrixXd covariance = ldlt.solve(Eigen::MatrixXd::Identity(n, n));

  // Camera centres c = -R^T t of frames 1..: their joint covariance through the derivative of c
  // with respect to (angle-axis, t), taken by central differences.
  const int m = 3 * (frames - 1);
  Eigen::MatrixXd J_centres = Eigen::MatrixXd::Zero(m, n);
  std::vector<Eigen::Vector3d> centres;
  auto centre = [](const core::PoseVector& v) {
    return Eigen::Vector3d(core::isometry_of(v).inverse().translation());
  };
  for (int f = 1; f < frames; ++f) {
    centres.push_back(centre(poses[f]));
    for (int k = 0; k < 6; ++k) {
      Eigen::Matrix<double, 6, 1> plus = poses[f], minus = poses[f];
      plus[k] += 1e-6;
      minus[k] -= 1e-6;
      J_centres.block<3, 1>(3 * (f - 1), 6 * (f - 1) + k) = (centre(plus) - centre(minus)) / 2e-6;
    }
  }
  const Eigen::MatrixXd covariance_centres = J_centres * covariance * J_centres.transpose();
  PositionBound bound;
  bound.rms_fixed_first_pose_m = std::sqrt(covariance_centres.trace() / (frames - 1));
  // A similarity's first-order effect on the centres: translation, rotation, scale about the mean.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& c : centres) mean += c;
  mean /= centres.size();
  Eigen::MatrixXd G(m, 7);
  for (int i = 0; i < frames - 1; ++i) {
    const Eigen::Vector3d c = centres[i] - mean;
    Eigen::Matrix3d skew;
    skew << 0, -c.z(), c.y(), c.z(), 0, -c.x(), -c.y(), c.x(), 0;
    G.block<3, 3>(3 * i, 0).setIdentity();
    G.block<3, 3>(3 * i, 3) = -skew;
    G.block<3, 1>(3 * i, 6) = c;
  }
  const Eigen::MatrixXd projector =
      Eigen::MatrixXd::Identity(m, m) - G * (G.transpose() * G).ldlt().solve(G.transpose());
  bound.rms_after_similarity_m =
      std::sqrt((projector * covariance_centres * projector.transpose()).trace() / (frames - 1));
  return bound;
}

}  // namespace omnisfm::sfm
