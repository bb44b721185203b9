#include "omnisfm/io/tracks_file.h"

#include <cmath>
#include <map>
#include <set>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {
namespace {

int integer_field(const VnlogReader& reader, size_t column, const std::string& name) {
  const double v = reader.number(column);
  if (!std::isfinite(v) || v < 0 || v != std::floor(v) || v > 2e9)
    throw InputError(reader.file(), reader.line(),
                     "column '" + name + "': '" + reader.text(column) +
                         "' is not a whole number from 0 to 2000000000");
  return static_cast<int>(v);
}

}  // namespace

TrackStream::TrackStream(const std::string& path, int image_width, int image_height)
    : reader_(path),
      columns_(reader_.columns({"frame", "track", "u", "v"})),
      image_width_(image_width),
      image_height_(image_height) {
  have_row_ = read_row();
}

bool TrackStream::read_row() {
  if (!reader_.next()) return false;
  row_line_ = reader_.line();
  row_.frame = integer_field(reader_, columns_[0], "frame");
  row_.track = integer_field(reader_, columns_[1], "track");
  // Each number read before the vector is filled: a throw inside Eigen's comma initializer
  // would leave it half-filled, which its destructor asserts against.
  const double u = reader_.number(columns_[2]);
  const double v = reader_.number(columns_[3]);
  row_.pixel = Eigen::Vector2d(u, v);
  if (!row_.pixel.allFinite())
    throw InputError(file(), row_line_, "the pixel (u, v) must be two finite numbers");
  if (image_width_ > 0 &&
      (row_.pixel.x() < -0.5 || row_.pixel.y() < -0.5 || row_.pixel.x() > image_width_ - 0.5 ||
       row_.pixel.y() > image_height_ - 0.5))
    throw InputError(file(), row_line_,
                     "pixel (" + reader_.text(columns_[2]) + ", " + reader_.text(columns_[3]) +
                         ") lies outside the " + std::to_string(image_width_) + "x" +
                         std::to_string(image_height_) + " image");
  return true;
}

bool TrackStream::next_frame(int* frame, std::vector<TrackObservation>* observations) {
  observations->clear();
  lines_.clear();
  if (!have_row_) return false;
  *frame = row_.frame;
  const long untracked = static_cast<long>(*frame) - previous_frame_ - 1;
  if (untracked > kMaxUntrackedFrames)
    throw InputError(file(), row_line_,
                     "frame " + std::to_string(*frame) + " comes " + std::to_string(untracked) +
                         " frames without a tracked feature after " +
                         (previous_frame_ < 0 ? std::string("the start")
                                              : "frame " + std::to_string(previous_frame_)) +
                         "; at most " + std::to_string(kMaxUntrackedFrames) +
                         " are taken (frame: the image's 0-based index)");
  previous_frame_ = *frame;
  std::set<int> in_frame;
  while (have_row_ && row_.frame == *frame) {
    if (!in_frame.insert(row_.track).second)
      throw InputError(file(), row_line_,
                       "track " + std::to_string(row_.track) + " appears twice in frame " +
                           std::to_string(row_.frame));
    observations->push_back(row_);
    lines_.push_back(row_line_);
    have_row_ = read_row();
  }
  if (have_row_ && row_.frame < *frame)
    throw InputError(file(), row_line_,
                     "frames must not decrease: frame " + std::to_string(row_.frame) +
                         " after frame " + std::to_string(*frame));
  return true;
}

std::vector<TrackObservation> read_tracks(const std::string& path, int image_width,
                                          int image_height) {
  TrackStream stream(path, image_width, image_height);
  std::vector<TrackObservation> tracks;
  std::map<int, std::pair<int, int>> count_and_line;  // per track
  int frame = 0;
  std::vector<TrackObservation> rows;
  while (stream.next_frame(&frame, &rows))
    for (size_t k = 0; k < rows.size(); ++k) {
      auto& [count, line] = count_and_line[rows[k].track];
      if (count++ == 0) line = stream.line(k);
      tracks.push_back(rows[k]);
    }
  for (const auto& [track, count_line] : count_and_line)
    if (count_line.first < 2)
      throw InputError(path, count_line.second,
                       "track " + std::to_string(track) + " has a single observation");
  return tracks;
}

void write_tracks(const std::string& path, const std::vector<TrackObservation>& tracks) {
  write_text_atomically(path, [&](std::ostream& out) {
    VnlogWriter writer(out, {"frame", "track", "u", "v"});
    for (const auto& o : tracks)
      writer.row({double(o.frame), double(o.track), o.pixel.x(), o.pixel.y()});
  });
}

}  // namespace omnisfm::io
