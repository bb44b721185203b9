#pragma once
// frames.vnl, beside a tracks file: `# frame timestamp image`, one row per image the tracks were
// measured in (DESIGN.md section 3).

#include <map>
#include <string>
#include <vector>

#include "omnisfm/track/track_images.h"

namespace omnisfm::track {

// Writes atomically. Image files are written relative to the folder of `path`, '-' when a frame
// has none (a video's); a frame without a timestamp gets its index. Throws std::runtime_error
// when the file cannot be written.
void write_frames_file(const std::string& path, const std::vector<TrackedFrame>& frames);

// An image's time, and the line of the file that gave it.
struct ImageTimestamp {
  double time = 0;
  int line = 0;
};

// Timestamps by image file name (its last path component), from a vnlog table with `image` and
// `timestamp` columns, such as the frames.vnl `omnisfm simulate` writes. Throws io::InputError
// naming the file and line for a missing column, a bad or non-finite number or a name given twice.
std::map<std::string, ImageTimestamp> read_image_timestamps(const std::string& path);

// Sets each frame's timestamp from `timestamps` by its file name. Throws io::InputError naming
// `timestamps_file` for a frame it has no timestamp for, and naming the line for a time that is
// not after the frame before's (the tracks' times go into TUM files, read in order).
void apply_timestamps(const std::map<std::string, ImageTimestamp>& timestamps,
                      const std::string& timestamps_file, std::vector<TrackedFrame>* frames);

}  // namespace omnisfm::track
