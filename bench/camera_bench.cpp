// Speed of the catadioptric camera model: projection without Jacobians, with d pixel / d X, and
// with every Jacobian; unprojection. Peers in the same binary: mrcal_project (LENSMODEL_OPENCV8)
// and cv::omnidir::projectPoints (Mei's unified model). Every benchmark reports the time per point.

#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <memory>
#include <opencv2/ccalib/omnidir.hpp>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/mirror_pose.h"
#include "omnisfm/camera/pinhole_camera.h"

// mrcal's C headers use anonymous structs in unions, which ISO C++ does not allow.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
extern "C" {
#include <mrcal/mrcal.h>
}
#pragma GCC diagnostic pop

namespace {

using omnisfm::camera::CatadioptricCamera;
using omnisfm::camera::ConicProfile;
using omnisfm::camera::EquiangularProfile;
using omnisfm::camera::MirrorPose;
using omnisfm::camera::PinholeCamera;
using omnisfm::camera::PinholeIntrinsics;

constexpr int kNumPoints = 4096;
constexpr unsigned kSeed = 2001;
constexpr double kMinDistance = 1.0;  // metres from the mirror along the reflected ray
constexpr double kMaxDistance = 10.0;
constexpr int kImageWidth = 1024;
constexpr int kImageHeight = 768;
constexpr double kPi = 3.14159265358979323846;

// Reports the CPU time per point ("per_point", in seconds) next to items_per_second.
void report_per_point(benchmark::State& state, int points_per_iteration) {
  state.SetItemsProcessed(state.iterations() * points_per_iteration);
  state.counters["per_point"] = benchmark::Counter(
      points_per_iteration,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

// ---------------------------------------------------------------------------------------------
// omnisfm cameras

enum class Rig { kEquiangularAligned, kEquiangularMisaligned, kConicHyperbolic };
constexpr int kNumRigs = 3;

CatadioptricCamera make_equiangular(const MirrorPose& pose) {
  PinholeIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 800;
  intrinsics.cx = 511.5;
  intrinsics.cy = 383.5;
  return CatadioptricCamera(std::make_unique<PinholeCamera>(intrinsics),
                            std::make_unique<EquiangularProfile>(5.0, 0.05, 0.02, 0.35), pose,
                            kImageWidth, kImageHeight);
}

// A hyperboloid with its outer focus at the camera centre: a central camera.
CatadioptricCamera make_conic_hyperbolic() {
  const double c = 1 / 0.03;
  const double kappa = -2;
  const double rho_min = 0.002, rho_max = 0.025;
  // The outer focus lies A (1 + e) in front of the apex (z0 = 0).
  const double semi_axis = (1 / c) / std::abs(1 + kappa);
  const double eccentricity = std::sqrt(-kappa);
  MirrorPose pose;
  pose.tz = semi_axis * (1 + eccentricity);
  // The rim (rho 0.025 at z ~ 0.081 m) then images ~370 px from the centre.
  PinholeIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 1200;
  intrinsics.cx = 511.5;
  intrinsics.cy = 383.5;
  return CatadioptricCamera(std::make_unique<PinholeCamera>(intrinsics),
                            std::make_unique<ConicProfile>(0.0, c, kappa, rho_min, rho_max), pose,
                            kImageWidth, kImageHeight);
}

CatadioptricCamera make_camera(Rig rig) {
  switch (rig) {
    case Rig::kEquiangularAligned:
      return make_equiangular(MirrorPose{});
    case Rig::kEquiangularMisaligned:
      return make_equiangular(MirrorPose{0.01, -0.015, 0.003, -0.002, 0.004});
    case Rig::kConicHyperbolic:
      break;
  }
  return make_conic_hyperbolic();
}

struct RigSamples {
  CatadioptricCamera camera;
  std::vector<Eigen::Vector2d> pixels;  // pixels with a valid reflected ray
  std::vector<Eigen::Vector3d> points;  // one point on each pixel's ray, projecting validly
  double mean_newton_iterations = 0;    // of the projections of the points
};

// Pixels drawn uniformly over the image and kept where the camera sees the mirror; each point lies
// 1-10 m along its pixel's reflected ray, so the points cover the whole field of view.
RigSamples make_rig_samples(Rig rig) {
  RigSamples samples{make_camera(rig), {}, {}};
  const CatadioptricCamera& camera = samples.camera;
  std::mt19937 random(kSeed);
  std::uniform_real_distribution<double> u(-0.5, camera.image_width() - 0.5);
  std::uniform_real_distribution<double> v(-0.5, camera.image_height() - 0.5);
  std::uniform_real_distribution<double> distance(kMinDistance, kMaxDistance);
  const int max_attempts = 100 * kNumPoints;
  for (int attempt = 0; attempt < max_attempts; ++attempt) {
    if (static_cast<int>(samples.points.size()) == kNumPoints) break;
    const Eigen::Vector2d pixel(u(random), v(random));
    Eigen::Vector3d origin, direction;
    if (!camera.unproject(pixel, &origin, &direction)) continue;
    const Eigen::Vector3d X = origin + distance(random) * direction;
    Eigen::Vector2d reprojected;
    omnisfm::camera::Reflection reflection;
    if (!camera.project(X, &reprojected, nullptr, nullptr, &reflection)) continue;
    samples.pixels.push_back(pixel);
    samples.points.push_back(X);
    samples.mean_newton_iterations += reflection.iterations;
  }
  if (!samples.points.empty()) samples.mean_newton_iterations /= samples.points.size();
  return samples;
}

// Built once per rig, on first use, so that sampling stays out of the timed loops.
const RigSamples& rig_samples(Rig rig) {
  static std::array<std::unique_ptr<RigSamples>, kNumRigs> cache;
  auto& entry = cache[static_cast<int>(rig)];
  if (!entry) entry = std::make_unique<RigSamples>(make_rig_samples(rig));
  return *entry;
}

bool has_enough_samples(benchmark::State& state, const RigSamples& samples) {
  if (static_cast<int>(samples.points.size()) == kNumPoints) return true;
  state.SkipWithError("too few pixels of the image see the mirror");
  return false;
}

enum class Jacobians { kNone, kPoint, kAll };

void BM_OmnisfmProject(benchmark::State& state, Rig rig, Jacobians jacobians) {
  const RigSamples& samples = rig_samples(rig);
  if (!has_enough_samples(state, samples)) return;
  const CatadioptricCamera& camera = samples.camera;
  Eigen::Vector2d pixel;
  Eigen::Matrix<double, 2, 3> J_X;
  omnisfm::camera::ParamsJacobian J_params;
  Eigen::Matrix<double, 2, 3>* J_X_out = jacobians == Jacobians::kNone ? nullptr : &J_X;
  omnisfm::camera::ParamsJacobian* J_params_out =
      jacobians == Jacobians::kAll ? &J_params : nullptr;
  for (auto _ : state) {
    for (const Eigen::Vector3d& X : samples.points) {
      bool valid = camera.project(X, &pixel, J_X_out, J_params_out);
      benchmark::DoNotOptimize(valid);
      benchmark::DoNotOptimize(pixel);
    }
    benchmark::ClobberMemory();
  }
  report_per_point(state, kNumPoints);
  state.counters["newton_iterations"] = samples.mean_newton_iterations;
}

void BM_OmnisfmUnproject(benchmark::State& state, Rig rig) {
  const RigSamples& samples = rig_samples(rig);
  if (!has_enough_samples(state, samples)) return;
  const CatadioptricCamera& camera = samples.camera;
  Eigen::Vector3d origin, direction;
  for (auto _ : state) {
    for (const Eigen::Vector2d& pixel : samples.pixels) {
      bool valid = camera.unproject(pixel, &origin, &direction);
      benchmark::DoNotOptimize(valid);
      benchmark::DoNotOptimize(origin);
      benchmark::DoNotOptimize(direction);
    }
    benchmark::ClobberMemory();
  }
  report_per_point(state, kNumPoints);
}

#define OMNISFM_CAMERA_BENCHMARKS(rig_name, rig)                                     \
  BENCHMARK_CAPTURE(BM_OmnisfmProject, rig_name/no_jacobians, rig, Jacobians::kNone); \
  BENCHMARK_CAPTURE(BM_OmnisfmProject, rig_name/J_X, rig, Jacobians::kPoint);         \
  BENCHMARK_CAPTURE(BM_OmnisfmProject, rig_name/J_X_J_params, rig, Jacobians::kAll);  \
  BENCHMARK_CAPTURE(BM_OmnisfmUnproject, rig_name, rig)

OMNISFM_CAMERA_BENCHMARKS(equiangular_aligned, Rig::kEquiangularAligned);
OMNISFM_CAMERA_BENCHMARKS(equiangular_misaligned, Rig::kEquiangularMisaligned);
OMNISFM_CAMERA_BENCHMARKS(conic_hyperbolic, Rig::kConicHyperbolic);

// ---------------------------------------------------------------------------------------------
// Peer: mrcal_project with LENSMODEL_OPENCV8

constexpr int kOpencv8NumIntrinsics = 12;
// fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6
constexpr std::array<double, kOpencv8NumIntrinsics> kOpencv8Intrinsics = {
    800, 800, 511.5, 383.5, -0.1, 0.01, 0.001, -0.001, 0.0, 0.001, -0.0005, 0.0001};

// Points 1-10 m in front of the camera, inside a ~100 x 80 degree field of view.
const std::vector<mrcal_point3_t>& pinhole_points() {
  static const std::vector<mrcal_point3_t> points = [] {
    std::mt19937 random(kSeed);
    std::uniform_real_distribution<double> a(-0.6, 0.6), b(-0.45, 0.45);
    std::uniform_real_distribution<double> depth(kMinDistance, kMaxDistance);
    std::vector<mrcal_point3_t> result(kNumPoints);
    for (mrcal_point3_t& p : result) {
      p.z = depth(random);
      p.x = a(random) * p.z;
      p.y = b(random) * p.z;
    }
    return result;
  }();
  return points;
}

mrcal_lensmodel_t opencv8_lensmodel() {
  mrcal_lensmodel_t lensmodel{};
  lensmodel.type = MRCAL_LENSMODEL_OPENCV8;
  return lensmodel;
}

// One mrcal_project call per point, as omnisfm is called.
void BM_MrcalProjectOpencv8(benchmark::State& state, bool gradients) {
  const std::vector<mrcal_point3_t>& points = pinhole_points();
  const mrcal_lensmodel_t lensmodel = opencv8_lensmodel();
  mrcal_point2_t q;
  std::array<mrcal_point3_t, 2> dq_dp;
  std::array<double, 2 * kOpencv8NumIntrinsics> dq_dintrinsics;
  mrcal_point3_t* dq_dp_out = gradients ? dq_dp.data() : nullptr;
  double* dq_dintrinsics_out = gradients ? dq_dintrinsics.data() : nullptr;
  for (auto _ : state) {
    for (const mrcal_point3_t& p : points) {
      bool valid = mrcal_project(&q, dq_dp_out, dq_dintrinsics_out, &p, 1, &lensmodel,
                                 kOpencv8Intrinsics.data());
      benchmark::DoNotOptimize(valid);
      benchmark::DoNotOptimize(q);
    }
    benchmark::ClobberMemory();
  }
  report_per_point(state, kNumPoints);
}

// All points in one call, mrcal's natural use.
void BM_MrcalProjectOpencv8Batch(benchmark::State& state, bool gradients) {
  const std::vector<mrcal_point3_t>& points = pinhole_points();
  const mrcal_lensmodel_t lensmodel = opencv8_lensmodel();
  std::vector<mrcal_point2_t> q(kNumPoints);
  std::vector<mrcal_point3_t> dq_dp(gradients ? 2 * kNumPoints : 0);
  std::vector<double> dq_dintrinsics(gradients ? 2 * kNumPoints * kOpencv8NumIntrinsics : 0);
  mrcal_point3_t* dq_dp_out = gradients ? dq_dp.data() : nullptr;
  double* dq_dintrinsics_out = gradients ? dq_dintrinsics.data() : nullptr;
  for (auto _ : state) {
    bool valid = mrcal_project(q.data(), dq_dp_out, dq_dintrinsics_out, points.data(), kNumPoints,
                               &lensmodel, kOpencv8Intrinsics.data());
    benchmark::DoNotOptimize(valid);
    benchmark::ClobberMemory();
  }
  report_per_point(state, kNumPoints);
}

BENCHMARK_CAPTURE(BM_MrcalProjectOpencv8, no_gradients, false);
BENCHMARK_CAPTURE(BM_MrcalProjectOpencv8, gradients, true);
BENCHMARK_CAPTURE(BM_MrcalProjectOpencv8Batch, no_gradients, false);
BENCHMARK_CAPTURE(BM_MrcalProjectOpencv8Batch, gradients, true);

// ---------------------------------------------------------------------------------------------
// Peer: cv::omnidir::projectPoints (Mei's unified model)

// Unit vectors up to 100 degrees from the optical axis, uniformly over that cap of the sphere.
cv::Mat sphere_points() {
  std::mt19937 random(kSeed);
  const double max_angle = 100.0 * kPi / 180.0;
  std::uniform_real_distribution<double> cos_angle(std::cos(max_angle), 1.0);
  std::uniform_real_distribution<double> azimuth(-kPi, kPi);
  cv::Mat points(1, kNumPoints, CV_64FC3);
  for (int i = 0; i < kNumPoints; ++i) {
    const double z = cos_angle(random);
    const double sin_angle = std::sqrt(1 - z * z);
    const double phi = azimuth(random);
    points.at<cv::Vec3d>(i) = cv::Vec3d(sin_angle * std::cos(phi), sin_angle * std::sin(phi), z);
  }
  return points;
}

// The OpenCV call takes the whole array: one call per point would measure cv::Mat overhead.
void BM_OpencvOmnidirProject(benchmark::State& state, bool jacobian) {
  const cv::Mat object_points = sphere_points();
  const cv::Vec3d rvec(0, 0, 0), tvec(0, 0, 0);
  const cv::Matx33d K(300, 0, 511.5, 0, 300, 383.5, 0, 0, 1);
  const cv::Vec4d D(-0.05, 0.01, 0.001, -0.001);  // k1 k2 p1 p2
  const double xi = 0.95;
  cv::Mat image_points, J;
  for (auto _ : state) {
    if (jacobian) {
      cv::omnidir::projectPoints(object_points, image_points, rvec, tvec, K, xi, D, J);
    } else {
      cv::omnidir::projectPoints(object_points, image_points, rvec, tvec, K, xi, D);
    }
    benchmark::DoNotOptimize(image_points.data);
    benchmark::ClobberMemory();
  }
  report_per_point(state, kNumPoints);
}

BENCHMARK_CAPTURE(BM_OpencvOmnidirProject, no_jacobian, false);
BENCHMARK_CAPTURE(BM_OpencvOmnidirProject, jacobian, true);

}  // namespace

BENCHMARK_MAIN();
