// frames.vnl, the image timestamps `track --timestamps` takes (track::read_image_timestamps).
#include <cmath>

#include "fuzz_contract.h"
#include "omnisfm/track/frames_file.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "frames.vnl");
  fuzz::expect_contract([&] {
    for (const auto& [image, timestamp] : track::read_image_timestamps(path)) {
      fuzz::require(!image.empty(), "a timestamp for an image with no name");
      fuzz::require(std::isfinite(timestamp.time), "a timestamp that is not finite");
    }
  });
  return 0;
}
