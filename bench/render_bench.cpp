// Speed of rendering what the rig sees: one 1024 x 768 frame of a rover-like scene (ground, the
// walls of a yard, boxes; the rig upright at 0.6 m) with 4 samples per pixel on 2 threads, and the
// PNG writing that follows it in `omnisfm simulate --render`. The rover sequence has 150 frames;
// the goal is 60 s for all of it, 400 ms per frame with its PNG. The peer in the same binary is the
// same image traced without culling, through Scene::intersect. Time is wall-clock; CPU is the
// process's, summed over the threads, which depends less on other load.

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scene.h"

namespace {

using namespace omnisfm::sim;

constexpr int kSamplesPerPixel = 4;
constexpr int kThreads = 2;
constexpr int kNumPoses = 8;

omnisfm::camera::CatadioptricCamera rover_camera() {
  return omnisfm::camera::CatadioptricCamera(
      std::make_unique<omnisfm::camera::PinholeCamera>(
          omnisfm::camera::PinholeIntrinsics{800, 800, 511.5, 383.5}),
      std::make_unique<omnisfm::camera::EquiangularProfile>(5.0, 0.05, 0.02, 0.35),
      {0.004, -0.006, 0.003, -0.002, 0.002}, 1024, 768);
}

// Ground, a 20 x 16 m yard walled 3 m high, and eight boxes of 6 faces: 53 quads.
Scene rover_scene() {
  Scene scene;
  scene.add_quad({{-30, -30, 0}, {60, 0, 0}, {0, 60, 0}, kGroundTexture});
  const Eigen::Vector3d ex(20, 0, 0), ey(0, 16, 0), ez(0, 0, 3), corner(-10, -8, 0);
  scene.add_quad({corner, ex, ez, kWallTexture});
  scene.add_quad({corner + ey, ex, ez, kWallTexture});
  scene.add_quad({corner, ey, ez, kWallTexture});
  scene.add_quad({corner + ex, ey, ez, kWallTexture});
  const double boxes[8][4] = {{2.5, 1.0, 0.8, 0.6}, {-3.0, 2.0, 1.2, 1.0}, {1.0, -4.0, 0.6, 0.4},
                              {-2.0, -3.0, 1.0, 0.8}, {5.0, -1.5, 1.5, 1.2}, {-6.0, 0.5, 0.9, 0.5},
                              {4.0, 4.5, 1.1, 0.9}, {-1.0, 5.5, 0.7, 1.4}};
  for (const auto& box : boxes) {
    const Eigen::Vector3d centre(box[0], box[1], 0);
    const double half = box[2] / 2;
    scene.add_box(centre - Eigen::Vector3d(half, half, 0),
                  centre + Eigen::Vector3d(half, half, box[3]), kBoxTexture);
  }
  return scene;
}

// Points along a short drive with yaw changes, the rig upright (z of C up) at 0.6 m.
std::vector<Eigen::Isometry3d> rover_poses() {
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < kNumPoses; ++k) {
    Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
    world_from_cam.linear() =
        Eigen::AngleAxisd(0.3 * k, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    world_from_cam.translation() << 0.4 * k - 1.5, 0.3 * std::sin(k), 0.6;
    poses.push_back(world_from_cam);
  }
  return poses;
}

const Renderer& rover_renderer() {
  static const Renderer renderer(rover_camera(), kSamplesPerPixel, kThreads);
  return renderer;
}

void BM_RenderRoverFrame(benchmark::State& state) {
  const Renderer& renderer = rover_renderer();
  const Scene scene = rover_scene();
  const std::vector<Eigen::Isometry3d> poses = rover_poses();
  int frame = 0;
  for (auto _ : state) {
    cv::Mat image = renderer.render(scene, poses[frame++ % kNumPoses]);
    benchmark::DoNotOptimize(image.data);
  }
  state.counters["rays"] = static_cast<double>(renderer.num_rays());
}
BENCHMARK(BM_RenderRoverFrame)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

void BM_RenderRoverFrameUnaccelerated(benchmark::State& state) {
  const Renderer& renderer = rover_renderer();
  const Scene scene = rover_scene();
  const std::vector<Eigen::Isometry3d> poses = rover_poses();
  int frame = 0;
  for (auto _ : state) {
    cv::Mat image = renderer.render_unaccelerated(scene, poses[frame++ % kNumPoses]);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_RenderRoverFrameUnaccelerated)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The PNG of a rendered frame; argument: zlib compression level.
void BM_WriteFramePng(benchmark::State& state) {
  const cv::Mat image = rover_renderer().render(rover_scene(), rover_poses()[0]);
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("render_bench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "000000.png").string();
  for (auto _ : state) write_png(path, image, static_cast<int>(state.range(0)));
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove_all(folder);
}
BENCHMARK(BM_WriteFramePng)
    ->Arg(kFastPngCompression)
    ->Arg(kSmallPngCompression)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Built once per camera: one exact unprojection per sample.
void BM_BuildRenderer(benchmark::State& state) {
  const omnisfm::camera::CatadioptricCamera camera = rover_camera();
  for (auto _ : state) {
    Renderer renderer(camera, static_cast<int>(state.range(0)), kThreads);
    benchmark::DoNotOptimize(renderer.num_rays());
  }
}
BENCHMARK(BM_BuildRenderer)
    ->Arg(4)
    ->Iterations(2)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
