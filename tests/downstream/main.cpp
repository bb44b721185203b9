// Projects one point with the default equiangular camera of the camera-file example; exits 0 iff
// the pixel is valid, finite and inside the image.

#include <cstdio>
#include <memory>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/mirror_pose.h"
#include "omnisfm/camera/pinhole_camera.h"

int main() {
  using namespace omnisfm::camera;
  PinholeIntrinsics intrinsics;
  intrinsics.fx = intrinsics.fy = 800;
  intrinsics.cx = 511.5;
  intrinsics.cy = 383.5;
  const CatadioptricCamera camera(std::make_unique<PinholeCamera>(intrinsics),
                                  std::make_unique<EquiangularProfile>(5.0, 0.05, 0.02, 0.35),
                                  MirrorPose{}, 1024, 768);

  // 2 m to the side and 1 m behind the camera: seen about 63 degrees from the mirror's axis.
  const Eigen::Vector3d X(2.0, 0.0, -1.0);
  Eigen::Vector2d pixel;
  if (!camera.project(X, &pixel) || !pixel.allFinite() || !camera.in_image(pixel)) {
    std::fprintf(stderr, "omnisfm_downstream: projection of (2, 0, -1) failed\n");
    return 1;
  }
  std::printf("%.6f %.6f\n", pixel.x(), pixel.y());
  return 0;
}
