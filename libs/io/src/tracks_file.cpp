#include "omnisfm/io/tracks_file.h"

#include <cmath>
#include <map>
#include <set>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {
namespace {

int integer_field(const VnlogTable& table, size_t row, size_t column, const std::string& name) {
  const double v = table.number(row, column);
  if (!std::isfinite(v) || v < 0 || v != std::floor(v) || v > 2e9)
    throw InputError(table.file(), table.line(row),
                     "column '" + name + "': '" + table.text(row, column) +
                         "' is not a non-negative integer");
  return static_cast<int>(v);
}

}  // namespace

std::vector<TrackObservation> read_tracks(const std::string& path, int image_width,
                                          int image_height) {
  const VnlogTable table = VnlogTable::read(path);
  const auto cols = table.columns({"frame", "track", "u", "v"});
  std::vector<TrackObservation> tracks;
  std::map<int, std::pair<int, int>> count_and_line;  // per track
  std::set<int> in_frame;
  int current_frame = -1;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    TrackObservation o;
    o.frame = integer_field(table, r, cols[0], "frame");
    o.track = integer_field(table, r, cols[1], "track");
    o.pixel << table.number(r, cols[2]), table.number(r, cols[3]);
    if (!o.pixel.allFinite())
      throw InputError(path, table.line(r), "the pixel (u, v) must be two finite numbers");
    if (image_width > 0 &&
        (o.pixel.x() < -0.5 || o.pixel.y() < -0.5 || o.pixel.x() > image_width - 0.5 ||
         o.pixel.y() > image_height - 0.5))
      throw InputError(path, table.line(r),
                       "pixel (" + table.text(r, cols[2]) + ", " + table.text(r, cols[3]) +
                           ") lies outside the " + std::to_string(image_width) + "x" +
                           std::to_string(image_height) + " image");
    if (o.frame < current_frame)
      throw InputError(path, table.line(r),
                       "frames must not decrease: frame " + std::to_string(o.frame) +
                           " after frame " + std::to_string(current_frame));
    if (o.frame != current_frame) in_frame.clear();
    current_frame = o.frame;
    if (!in_frame.insert(o.track).second)
      throw InputError(path, table.line(r),
                       "track " + std::to_string(o.track) + " appears twice in frame " +
                           std::to_string(o.frame));
    auto& [count, line] = count_and_line[o.track];
    if (count++ == 0) line = table.line(r);
    tracks.push_back(o);
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
