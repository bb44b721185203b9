#include "omnisfm/sfm/track_triangulation.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace omnisfm::sfm {
namespace {

// Sum of squared reprojection errors, and the Gauss-Newton normal equations when asked; false
// where the point does not project into some sighting.
bool reprojection(const camera::CatadioptricCamera& camera,
                  const std::vector<TrackSighting>& sightings, const Eigen::Vector3d& X,
                  double* cost, Eigen::Matrix3d* JtJ, Eigen::Vector3d* Jtr,
                  double* largest = nullptr) {
  *cost = 0;
  if (JtJ) JtJ->setZero(), Jtr->setZero();
  if (largest) *largest = 0;
  for (const auto& s : sightings) {
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 3> J_X;
    if (!camera.project(s.cam_from_world * X, &pixel, JtJ ? &J_X : nullptr)) return false;
    const Eigen::Vector2d r = s.pixel - pixel;
    *cost += r.squaredNorm();
    if (largest) *largest = std::max(*largest, r.norm());
    if (JtJ) {
      const Eigen::Matrix<double, 2, 3> J = J_X * s.cam_from_world.linear();
      *JtJ += J.transpose() * J;
      *Jtr += J.transpose() * r;
    }
  }
  return true;
}

}  // namespace

TriangulatedTrack triangulate_track(const camera::CatadioptricCamera& camera,
                                    const std::vector<TrackSighting>& sightings,
                                    double min_parallax_rad) {
  TriangulatedTrack out;
  if (sightings.size() < 2) return out;
  // The point closest to every ray: sum (I - d d^T) (X - o) = 0.
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  Eigen::Vector3d first_direction;
  double widest = 0;
  for (size_t i = 0; i < sightings.size(); ++i) {
    Eigen::Vector3d origin_C, direction_C;
    if (!camera.unproject(sightings[i].pixel, &origin_C, &direction_C)) return out;
    const Eigen::Isometry3d world_from_cam = sightings[i].cam_from_world.inverse();
    const Eigen::Vector3d o = world_from_cam * origin_C;
    const Eigen::Vector3d d = world_from_cam.linear() * direction_C;
    if (i == 0) first_direction = d;
    widest = std::max(widest, std::acos(std::clamp(d.dot(first_direction), -1.0, 1.0)));
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - d * d.transpose();
    A += across;
    b += across * o;
  }
  if (widest < min_parallax_rad) return out;
  Eigen::Vector3d X = A.ldlt().solve(b);
  if (!X.allFinite()) return out;

  // Levenberg-Marquardt on the pixels from there, a few steps: the rays' point is close.
  double cost;
  Eigen::Matrix3d JtJ;
  Eigen::Vector3d Jtr;
  if (!reprojection(camera, sightings, X, &cost, &JtJ, &Jtr)) return out;
  double damping = 1e-6;
  for (int iteration = 0; iteration < 20 && damping < 1e6; ++iteration) {
    Eigen::Matrix3d damped = JtJ;
    damped.diagonal() *= 1 + damping;
    const Eigen::Vector3d step = damped.ldlt().solve(Jtr);
    double trial_cost;
    if (step.allFinite() && reprojection(camera, sightings, X + step, &trial_cost, nullptr, nullptr) &&
        trial_cost < cost) {
      X += step;
      const bool settled = cost - trial_cost < 1e-10 * (1 + cost);
      reprojection(camera, sightings, X, &cost, &JtJ, &Jtr);
      damping = std::max(1e-9, damping / 10);
      if (settled) break;
    } else {
      damping *= 10;
    }
  }
  double largest;
  if (!reprojection(camera, sightings, X, &cost, nullptr, nullptr, &largest)) return out;
  out.valid = true;
  out.point = X;
  out.largest_residual_px = largest;
  out.rms_px = std::sqrt(cost / (2.0 * sightings.size()));
  return out;
}

}  // namespace omnisfm::sfm
