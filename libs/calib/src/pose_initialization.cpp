#include "omnisfm/calib/pose_initialization.h"

#include <opengv/absolute_pose/NoncentralAbsoluteAdapter.hpp>
#include <opengv/absolute_pose/methods.hpp>
#include <opengv/sac/Ransac.hpp>
#include <opengv/sac_problems/absolute_pose/AbsolutePoseSacProblem.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

namespace omnisfm::calib {

bool initial_pose(const camera::CatadioptricCamera& camera,
                  const std::vector<Eigen::Vector3d>& points_object,
                  const std::vector<Eigen::Vector2d>& pixels, Eigen::Isometry3d* cam_from_object) {
  // Every ray is its own viewpoint: offset at its mirror point, bearing its direction, frame C.
  opengv::bearingVectors_t bearings;
  opengv::absolute_pose::NoncentralAbsoluteAdapter::camCorrespondences_t correspondences;
  opengv::points_t points;
  opengv::translations_t offsets;
  opengv::rotations_t rotations;
  for (size_t i = 0; i < pixels.size(); ++i) {
    Eigen::Vector3d origin, direction;
    if (!camera.unproject(pixels[i], &origin, &direction)) continue;
    correspondences.push_back(static_cast<int>(bearings.size()));
    bearings.push_back(direction);
    offsets.push_back(origin);
    rotations.push_back(Eigen::Matrix3d::Identity());
    points.push_back(points_object[i]);
  }
  if (bearings.size() < 6) return false;

  opengv::absolute_pose::NoncentralAbsoluteAdapter adapter(bearings, correspondences, points,
                                                           offsets, rotations);
  using Problem = opengv::sac_problems::absolute_pose::AbsolutePoseSacProblem;
  opengv::sac::Ransac<Problem> ransac;
  // A fixed seed: the same inputs give the same calibration.
  ransac.sac_model_ = std::make_shared<Problem>(adapter, Problem::GP3P, /*randomSeed=*/false);
  // Loose enough for a nominal, uncalibrated model (a misaligned mirror bends rays by tens of
  // milliradians); the calibration that follows does the fine work.
  ransac.threshold_ = 1.0 - std::cos(0.05);
  ransac.max_iterations_ = 500;
  if (!ransac.computeModel() || ransac.inliers_.size() < 6) return false;

  // World (object) from viewpoint, [R | t].
  auto angular_error = [&](const opengv::transformation_t& T) {
    double sum = 0;
    for (int i : ransac.inliers_) {
      const Eigen::Vector3d in_cam =
          T.leftCols<3>().transpose() * (points[i] - T.col(3)) - offsets[i];
      sum += std::acos(std::clamp(in_cam.normalized().dot(bearings[i]), -1.0, 1.0));
    }
    return sum / ransac.inliers_.size();
  };
  opengv::transformation_t world_from_cam = ransac.model_coefficients_;
  // Minimal solutions are noisy on a nearly central rig: polish on all inliers.
  adapter.setR(world_from_cam.leftCols<3>());
  adapter.sett(world_from_cam.col(3));
  const opengv::transformation_t refined =
      opengv::absolute_pose::optimize_nonlinear(adapter, ransac.inliers_);
  if (refined.allFinite() && angular_error(refined) < angular_error(world_from_cam))
    world_from_cam = refined;
  Eigen::Isometry3d object_from_cam = Eigen::Isometry3d::Identity();
  object_from_cam.linear() = world_from_cam.leftCols<3>();
  object_from_cam.translation() = world_from_cam.col(3);
  if (!object_from_cam.matrix().allFinite()) return false;
  *cam_from_object = object_from_cam.inverse();
  return true;
}

}  // namespace omnisfm::calib
