// Reproduces Figure 2 of Strelow et al. (IROS 2001): a room whose walls carry vertical black lines,
// seen by the default equiangular rig with the mirror aligned (the lines image as radial lines),
// translated 2 cm along x, and rotated 0.2 rad about y (the lines bend).
//
//   figure2 OUTPUT_DIR    writes figure2-aligned.png, figure2-translated.png, figure2-rotated.png

#include <cstdio>
#include <exception>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <string>

#include "omnisfm/camera/mirror_pose.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/shared_data.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scene.h"

namespace {

using omnisfm::camera::MirrorPose;
using namespace omnisfm::sim;

constexpr int kSamplesPerPixel = 16;
// Half size keeps the images small enough for the repository.
const cv::Size kFigureSize(512, 384);

// A 6 x 5 x 3 m room with striped walls, seen from its middle at 1.2 m.
Scene striped_room() {
  Scene scene;
  const Eigen::Vector3d ex(6, 0, 0), ey(0, 5, 0), ez(0, 0, 3);
  scene.add_quad({Eigen::Vector3d::Zero(), ex, ey, kPlainTexture});
  scene.add_quad({ez, ex, ey, kPlainTexture});
  // edge_u horizontal on every wall, so that the stripes are vertical.
  scene.add_quad({Eigen::Vector3d::Zero(), ex, ez, kStripedWallTexture});
  scene.add_quad({ey, ex, ez, kStripedWallTexture});
  scene.add_quad({Eigen::Vector3d::Zero(), ey, ez, kStripedWallTexture});
  scene.add_quad({ex, ey, ez, kStripedWallTexture});
  return scene;
}

// The rig upright: mirror above the camera, z of C along the world's up.
Eigen::Isometry3d rig_pose() {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.translation() << 3.0, 2.5, 1.2;
  return world_from_cam;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: figure2 OUTPUT_DIR\n");
    return 2;
  }
  try {
    const std::filesystem::path folder(argv[1]);
    std::filesystem::create_directories(folder);
    omnisfm::camera::CatadioptricCamera camera =
        omnisfm::io::read_camera_file(omnisfm::io::default_camera_file());
    const Scene scene = striped_room();

    struct Variant {
      const char* name;
      MirrorPose misalignment;
    };
    MirrorPose translated, rotated;
    translated.tx = 0.02;
    rotated.ry = 0.2;
    for (const Variant& variant : {Variant{"aligned", MirrorPose()},
                                   Variant{"translated", translated},
                                   Variant{"rotated", rotated}}) {
      camera.set_mirror_pose(variant.misalignment);
      const Renderer renderer(camera, kSamplesPerPixel);
      cv::Mat figure;
      cv::resize(renderer.render(scene, rig_pose()), figure, kFigureSize, 0, 0, cv::INTER_AREA);
      const std::string name = "figure2-" + std::string(variant.name) + ".png";
      const std::string path = (folder / name).string();
      write_png(path, figure, kSmallPngCompression);
      std::printf("%s\n", path.c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "figure2: %s\n", e.what());
    return 1;
  }
  return 0;
}
