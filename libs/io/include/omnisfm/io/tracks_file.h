#pragma once
// Feature tracks: `tracks.vnl` with `# frame track u v` (frame: 0-based image index, track:
// integer id), rows sorted by frame.

#include <Eigen/Core>
#include <string>
#include <vector>

namespace omnisfm::io {

struct TrackObservation {
  int frame = 0;
  int track = 0;
  Eigen::Vector2d pixel{0, 0};
};

// Throws InputError naming the file and line for: missing columns, non-integer frame or track,
// missing or non-finite pixels, frames out of order, a track seen twice in a frame, a pixel
// outside the image (when image_width/height > 0), and a track with a single observation.
std::vector<TrackObservation> read_tracks(const std::string& path, int image_width = 0,
                                          int image_height = 0);

// Writes atomically; throws std::runtime_error when it cannot.
void write_tracks(const std::string& path, const std::vector<TrackObservation>& tracks);

}  // namespace omnisfm::io
