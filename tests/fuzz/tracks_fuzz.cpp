// tracks.vnl, whole (io::read_tracks) and streamed (io::TrackStream): rows come out in frame
// order with finite pixels inside the image, and whole files hold no track seen once.
#include <cmath>
#include <map>

#include "fuzz_contract.h"
#include "omnisfm/io/tracks_file.h"

using namespace omnisfm;

namespace {

constexpr int kWidth = 640, kHeight = 480;

bool inside(const Eigen::Vector2d& pixel) {
  return pixel.allFinite() && pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() <= kWidth - 0.5 &&
         pixel.y() <= kHeight - 0.5;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "tracks.vnl");
  fuzz::expect_contract([&] {
    const auto rows = io::read_tracks(path, kWidth, kHeight);
    std::map<int, int> seen;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      fuzz::require(inside(rows[i].pixel), "a pixel outside the image");
      fuzz::require(rows[i].frame >= 0, "a negative frame");
      if (i > 0) fuzz::require(rows[i].frame >= rows[i - 1].frame, "frames out of order");
      ++seen[rows[i].track];
    }
    for (const auto& [track, count] : seen) fuzz::require(count >= 2, "a track seen once");
  });
  fuzz::expect_contract([&] {
    io::TrackStream stream(path, kWidth, kHeight);
    int frame = -1, previous = -1;
    std::vector<core::TrackObservation> observations;
    while (stream.next_frame(&frame, &observations)) {
      fuzz::require(frame > previous, "streamed frames out of order");
      fuzz::require(!observations.empty(), "a streamed frame without rows");
      for (const auto& observation : observations)
        fuzz::require(observation.frame == frame && inside(observation.pixel),
                      "a streamed row of another frame or outside the image");
      previous = frame;
    }
  });
  return 0;
}
