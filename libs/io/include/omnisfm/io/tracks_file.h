#pragma once
// Feature tracks: `tracks.vnl` with `# frame track u v` (frame: 0-based image index, track:
// integer id), rows sorted by frame.
//
// Every frame up to the last is an image with a pose (the estimators step through each one, and
// write one pose per frame), so a frame id costs memory and time whether tracked or not. More
// than kMaxUntrackedFrames frames in a row without a tracked feature (from frame 0 to the first
// row, or between two rows) are refused as bad input: a frame id such as 2e9 is damage, not a
// sequence.

#include <Eigen/Core>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "omnisfm/core/track_observation.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {

inline constexpr int kMaxUntrackedFrames = 1000;

// The observations this file holds are the core vocabulary's.
using core::TrackObservation;

// tracks.vnl read one frame at a time, for sequences of any length, with read_tracks' checks on
// each row; a track with a single observation is not refused (that needs the whole file).
class TrackStream {
 public:
  // Throws InputError naming the file when it cannot be read or lacks a column.
  TrackStream(const std::string& path, int image_width = 0, int image_height = 0);
  // The next frame that has observations: its index and its rows, in the file's order. False at
  // the end. Throws InputError naming the file and line for a bad row.
  bool next_frame(int* frame, std::vector<TrackObservation>* observations);
  // The file line of the n-th observation next_frame returned last.
  int line(std::size_t n) const { return lines_[n]; }
  const std::string& file() const { return reader_.file(); }

 private:
  bool read_row();  // into row_, false at the end

  VnlogReader reader_;
  std::vector<std::size_t> columns_;
  int image_width_, image_height_;
  bool have_row_ = false;
  TrackObservation row_;
  int row_line_ = 0;
  int previous_frame_ = -1;
  std::vector<int> lines_;
};

// Throws InputError naming the file and line for: missing columns, non-integer frame or track,
// missing or non-finite pixels, frames out of order, more than kMaxUntrackedFrames frames
// without a row, a track seen twice in a frame, a pixel outside the image (when
// image_width/height > 0), and a track with a single observation.
std::vector<TrackObservation> read_tracks(const std::string& path, int image_width = 0,
                                          int image_height = 0);

// Writes atomically; throws std::runtime_error when it cannot.
void write_tracks(const std::string& path, const std::vector<TrackObservation>& tracks);

}  // namespace omnisfm::io
