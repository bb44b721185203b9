// The camera INI file (io::read_camera_file) and its calibration covariance section: a camera
// that reads back projects to finite pixels or says it cannot, and unprojects to unit rays.
#include <Eigen/Core>
#include <cmath>

#include "fuzz_contract.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/io/camera_file.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "camera.ini");
  fuzz::expect_contract([&] {
    const camera::CatadioptricCamera camera = io::read_camera_file(path);
    fuzz::require(camera.image_width() > 0 && camera.image_height() > 0, "a camera of no size");
    for (const Eigen::Vector3d& X :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.3, -2, 0.5), Eigen::Vector3d(0, 0, -1)}) {
      Eigen::Vector2d pixel;
      if (camera.project(X, &pixel)) fuzz::require(pixel.allFinite(), "a projection to NaN");
    }
    const Eigen::Vector2d centre(camera.image_width() / 2.0, camera.image_height() / 2.0);
    Eigen::Vector3d origin, direction;
    if (camera.unproject(centre, &origin, &direction))
      fuzz::require(origin.allFinite() && std::abs(direction.norm() - 1) < 1e-6,
                    "an unprojection that is not a unit ray");
  });
  fuzz::expect_contract([&] { io::read_camera_covariance(path); });
  return 0;
}
