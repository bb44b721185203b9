#pragma once
// Checkerboard views of a known catadioptric camera, for tests: boards of 6 x 7 points 3 cm apart,
// 0.35-0.5 m from the mirror, all around it, each facing the mirror, with Gaussian pixel noise.

#include <Eigen/Geometry>
#include <memory>
#include <random>
#include <vector>

#include "omnisfm/calib/calibration_problem.h"
#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/pinhole_camera.h"

namespace omnisfm::calib::testing {

// A hyperbolic mirror on a pinhole, misaligned a little and off its focus (so noncentral).
inline camera::CatadioptricCamera true_hyperbolic_rig() {
  camera::PinholeIntrinsics k;
  k.fx = 700;
  k.fy = 705;
  k.cx = 515;
  k.cy = 390;
  const double A = 0.03 / 0.8, e = std::sqrt(1.8);  // R = 0.03 m, kappa = -1.8
  camera::MirrorPose pose;
  pose.rx = 0.02;
  pose.ry = -0.015;
  pose.tx = 0.002;
  pose.ty = -0.001;
  pose.tz = A * (1 + e) + 0.003;
  return camera::CatadioptricCamera(std::make_unique<camera::PinholeCamera>(k),
                                    std::make_unique<camera::ConicProfile>(0, 1 / 0.03, -1.8,
                                                                           0.001, 0.07),
                                    pose, 1024, 768);
}

// The starting guess a user would write: the nominal mirror (kappa -2, the pinhole at its outer
// focus, aligned), a rounded focal length, the image centre off by a few pixels.
inline camera::CatadioptricCamera nominal_hyperbolic_rig() {
  camera::PinholeIntrinsics k;
  k.fx = k.fy = 770;
  k.cx = 520;
  k.cy = 385;
  camera::MirrorPose pose;
  pose.tz = 0.03 * (1 + std::sqrt(2.0));
  return camera::CatadioptricCamera(std::make_unique<camera::PinholeCamera>(k),
                                    std::make_unique<camera::ConicProfile>(0, 1 / 0.03, -2.0,
                                                                           0.001, 0.07),
                                    pose, 1024, 768);
}

inline std::vector<Eigen::Vector3d> board_points() {
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 6; ++j) points.emplace_back(0.03 * i, 0.03 * j, 0);
  return points;
}

// `count` views whose every corner projects into the image; the true poses in cam_from_object.
inline std::vector<CalibrationView> board_views(const camera::CatadioptricCamera& truth, int count,
                                                double noise_px, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0, 1);
  std::normal_distribution<double> noise(0, noise_px);
  const std::vector<Eigen::Vector3d> points = board_points();
  const Eigen::Vector3d board_centre(0.09, 0.075, 0);
  // Around the mirror's inner focus, roughly: the mirror sits along +z of frame C.
  const Eigen::Vector3d focus(0, 0, 0.1);
  std::vector<CalibrationView> views;
  for (int attempt = 0; attempt < 1000 && static_cast<int>(views.size()) < count; ++attempt) {
    const double azimuth = 2 * M_PI * (views.size() + 0.3 * uniform(rng)) / count;
    const double elevation = -0.5 + 0.75 * uniform(rng);  // about the focus's horizontal plane
    const double distance = 0.35 + 0.15 * uniform(rng);
    const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                    std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
    // The board faces the focus, turned a little about its normal and tilted.
    const Eigen::Vector3d normal = -direction;
    Eigen::Vector3d x_axis = normal.cross(Eigen::Vector3d::UnitZ()).normalized();
    x_axis = Eigen::AngleAxisd(0.6 * (uniform(rng) - 0.5), normal) * x_axis;
    const Eigen::Vector3d y_axis = normal.cross(x_axis);
    Eigen::Matrix3d R;
    R << x_axis, y_axis, normal;
    R = Eigen::AngleAxisd(0.4 * (uniform(rng) - 0.5), x_axis) * R;
    Eigen::Isometry3d cam_from_object = Eigen::Isometry3d::Identity();
    cam_from_object.linear() = R;
    cam_from_object.translation() = focus + distance * direction - R * board_centre;

    CalibrationView view;
    view.name = "board " + std::to_string(views.size());
    view.cam_from_object = cam_from_object;
    bool all_visible = true;
    for (std::size_t i = 0; i < points.size() && all_visible; ++i) {
      Eigen::Vector2d pixel;
      all_visible = truth.project(cam_from_object * points[i], &pixel) && truth.in_image(pixel);
      view.points.push_back(points[i]);
      const double noise_y = noise(rng);  // before x: arguments have no order of evaluation
      const double noise_x = noise(rng);
      view.pixels.push_back(pixel + Eigen::Vector2d(noise_x, noise_y));
      view.point_ids.push_back(static_cast<int>(i));
    }
    if (all_visible) views.push_back(view);
  }
  return views;
}

}  // namespace omnisfm::calib::testing
