// mrcal's corners.vnl (io::read_corners): every image has one flag per corner, and the detected
// ones have finite pixels.
#include "fuzz_contract.h"
#include "omnisfm/io/checkerboard_files.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "corners.vnl");
  fuzz::expect_contract([&] {
    for (const auto& image : io::read_corners(path)) {
      fuzz::require(image.pixels.size() == image.detected.size(), "a flag missing for a corner");
      for (std::size_t i = 0; i < image.pixels.size(); ++i)
        if (image.detected[i]) fuzz::require(image.pixels[i].allFinite(), "a detected NaN corner");
    }
  });
  return 0;
}
