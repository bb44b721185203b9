// An mrcal .cameramodel, read as the inner camera of a camera INI file (inner = mrcal), which is
// how every verb reaches it.
#include <cstring>

#include "fuzz_contract.h"
#include "omnisfm/io/camera_file.h"

using namespace omnisfm;

namespace {

const char kCameraIni[] =
    "[omni_camera]\n"
    "image_width = 1280\nimage_height = 960\n"
    "inner = mrcal\ninner_cameramodel = inner.cameramodel\n"
    "mirror = conic\nconic_z0 = 0.0266\nconic_c = 0.0375\nconic_kappa = -2.1\n"
    "mirror_rho_min = 0.004\nmirror_rho_max = 0.02\nmirror_tz = 0.06\n";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string ini = fuzz::write_input(
      reinterpret_cast<const std::uint8_t*>(kCameraIni), std::strlen(kCameraIni), "camera.ini");
  fuzz::write_input(data, size, "inner.cameramodel");
  fuzz::expect_contract([&] { io::read_camera_file(ini); });
  return 0;
}
