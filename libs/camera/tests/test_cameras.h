#pragma once
// Cameras that every test of the catadioptric model runs on: each mirror profile with each inner
// camera it is used with, aligned and misaligned.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/mrcal_camera.h"
#include "omnisfm/camera/orthographic_camera.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/camera/table_profile.h"

namespace omnisfm::camera::testing {

inline std::unique_ptr<PinholeCamera> default_pinhole(bool distorted = false) {
  PinholeIntrinsics k{800, 805, 511.5, 383.5};
  if (distorted) {
    k.k1 = -0.08;
    k.k2 = 0.012;
    k.p1 = 0.0007;
    k.p2 = -0.0004;
    k.k3 = -0.001;
  }
  return std::make_unique<PinholeCamera>(k);
}

inline std::unique_ptr<EquiangularProfile> default_equiangular() {
  return std::make_unique<EquiangularProfile>(5.0, 0.05, 0.02, 0.35);
}

// A hyperboloid with its outer focus at the pinhole's centre when aligned (central camera).
inline CatadioptricCamera hyperbolic_camera(const MirrorPose& misalignment = {}) {
  auto mirror = std::make_unique<ConicProfile>(0.0, 1 / 0.03, -2.0, 0.002, 0.025);
  MirrorPose pose = misalignment;
  pose.tz += -mirror->outer_focus_z();
  return CatadioptricCamera(std::make_unique<PinholeCamera>(PinholeIntrinsics{1000, 1000, 511.5, 383.5}),
                            std::move(mirror), pose, 1024, 768);
}

// A paraboloid looked at by a telecentric lens (central camera).
inline CatadioptricCamera parabolic_camera(const MirrorPose& misalignment = {}) {
  auto mirror = std::make_unique<ConicProfile>(0.0, 1 / 0.02, -1.0, 0.001, 0.03);
  MirrorPose pose = misalignment;
  pose.tz += 0.1;
  return CatadioptricCamera(
      std::make_unique<OrthographicCamera>(OrthographicIntrinsics{12000, 12000, 511.5, 383.5}),
      std::move(mirror), pose, 1024, 768);
}

// A tabulated profile sampled from a sphere: the spline must reproduce it.
inline std::unique_ptr<TableProfile> sampled_sphere_profile(double radius, int samples) {
  std::vector<double> rho, z;
  for (int i = 0; i < samples; ++i) {
    const double r = 0.03 * i / (samples - 1);
    rho.push_back(r);
    z.push_back(radius - std::sqrt(radius * radius - r * r));
  }
  return std::make_unique<TableProfile>(rho, z, 0.002, 0.028);
}

// A LENSMODEL_OPENCV8 inner camera read through a real .cameramodel file.
inline std::string write_opencv8_cameramodel() {
  const std::string path = ::testing::TempDir() + "/inner_opencv8.cameramodel";
  std::ofstream f(path);
  f << "{\n 'lensmodel': 'LENSMODEL_OPENCV8',\n"
       " 'intrinsics': [ 790.0, 795.0, 512.5, 382.0, -0.05, 0.01, 0.0006, -0.0003, 0.0,"
       " 0.001, 0.0005, 0.0001 ],\n"
       " 'imagersize': [ 1024, 768 ],\n 'extrinsics': [ 0, 0, 0, 0, 0, 0 ]\n}\n";
  return path;
}

// d f / d x at 0 by the five-point central stencil: truncation O(h^4), so steps can be large
// enough to keep rounding noise near 1e-9 pixel per unit.
template <typename F>
auto five_point_derivative(const F& f, double h) {
  using Value = decltype(f(h));
  const Value far_minus = f(-2 * h), far_plus = f(2 * h);
  const Value near_minus = f(-h), near_plus = f(h);
  return Value(((far_minus - far_plus) + 8 * (near_plus - near_minus)) / (12 * h));
}

// Tolerance for comparing an analytic Jacobian column with five_point_derivative: relative 1e-6
// of the column, plus the rounding floor of the difference itself.
inline double derivative_tolerance(double column_norm) { return 1e-6 * column_norm + 1e-8; }

struct NamedCamera {
  std::string name;
  std::function<CatadioptricCamera()> make;
};

// Misalignment at the edge of the paper's Figure 2 range (2 cm, 0.2 rad) and a realistic one.
inline MirrorPose strong_misalignment() { return {0.12, -0.2, 0.02, -0.015, 0.01}; }
inline MirrorPose small_misalignment() { return {0.004, -0.006, 0.003, -0.002, 0.002}; }

inline std::vector<NamedCamera> contract_cameras() {
  auto equiangular = [](const MirrorPose& pose, bool distorted) {
    return [pose, distorted] {
      return CatadioptricCamera(default_pinhole(distorted), default_equiangular(), pose, 1024, 768);
    };
  };
  return {
      {"EquiangularAligned", equiangular({}, false)},
      {"EquiangularSmallMisalignment", equiangular(small_misalignment(), false)},
      {"EquiangularStrongMisalignment", equiangular(strong_misalignment(), false)},
      {"EquiangularDistortedPinhole", equiangular(small_misalignment(), true)},
      {"EquiangularMrcalOpencv8",
       [] {
         return CatadioptricCamera(
             std::make_unique<MrcalCamera>(MrcalCamera::from_file(write_opencv8_cameramodel())),
             default_equiangular(), small_misalignment(), 1024, 768);
       }},
      {"HyperbolicCentral", [] { return hyperbolic_camera(); }},
      {"HyperbolicMisaligned", [] { return hyperbolic_camera(strong_misalignment()); }},
      {"ParabolicOrthographic", [] { return parabolic_camera(); }},
      {"ParabolicOrthographicMisaligned",
       [] { return parabolic_camera({0.05, -0.08, 0.004, 0.003, 0.0}); }},
      {"SphericalPinhole",
       [] {
         return CatadioptricCamera(default_pinhole(),
                                   std::make_unique<ConicProfile>(0.0, 1 / 0.05, 0.0, 0.002, 0.03),
                                   {0.01, 0.02, 0.002, -0.001, 0.12}, 1024, 768);
       }},
      {"EllipsoidalPinhole",
       [] {
         return CatadioptricCamera(default_pinhole(),
                                   std::make_unique<ConicProfile>(0.0, 1 / 0.04, -0.5, 0.002, 0.03),
                                   {-0.01, 0.015, 0.001, 0.002, 0.1}, 1024, 768);
       }},
      {"TablePinhole",
       [] {
         return CatadioptricCamera(default_pinhole(), sampled_sphere_profile(0.05, 40),
                                   {0.01, -0.01, 0.002, 0.001, 0.12}, 1024, 768);
       }},
  };
}

}  // namespace omnisfm::camera::testing
