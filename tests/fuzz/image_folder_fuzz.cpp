// An image folder (track::ImageSequence): the first byte splits the rest into two image files,
// which must come out as 8-bit grey frames of one size, or as an InputError naming the image.
#include <opencv2/core.hpp>

#include "fuzz_contract.h"
#include "omnisfm/track/image_sequence.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t split = 1 + (size - 1) * data[0] / 255;
  fuzz::write_input(data + 1, split - 1, "images/0000.png");
  fuzz::write_input(data + split, size - split, "images/0001.png");
  fuzz::expect_contract([&] {
    track::ImageSequence sequence(fuzz::scratch_folder() + "/images");
    track::SequenceFrame frame;
    cv::Size first;
    while (sequence.next(&frame)) {
      fuzz::require(frame.image.type() == CV_8UC1 && !frame.image.empty(),
                    "a frame not 8-bit grey");
      if (first.empty()) first = frame.image.size();
      fuzz::require(frame.image.size() == first, "frames of different sizes");
    }
  });
  return 0;
}
