#include "omnisfm/track/frames_file.h"

#include <cmath>
#include <filesystem>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::track {

namespace fs = std::filesystem;

void write_frames_file(const std::string& path, const std::vector<TrackedFrame>& frames) {
  const fs::path folder = fs::absolute(path).parent_path();
  io::write_text_atomically(path, [&](std::ostream& out) {
    io::VnlogWriter writer(out, {"frame", "timestamp", "image"});
    for (const TrackedFrame& f : frames) {
      std::string image = "-";
      if (!f.file.empty()) {
        const fs::path relative =
            fs::absolute(f.file).lexically_normal().lexically_relative(folder);
        image = relative.empty() ? fs::absolute(f.file).string() : relative.string();
      }
      const double time = std::isnan(f.timestamp) ? f.index : f.timestamp;
      writer.row_texts({std::to_string(f.index), io::VnlogWriter::field(time), image});
    }
  });
}

std::map<std::string, ImageTimestamp> read_image_timestamps(const std::string& path) {
  const io::VnlogTable table = io::VnlogTable::read(path);
  const auto columns = table.columns({"image", "timestamp"});
  std::map<std::string, ImageTimestamp> timestamps;
  for (size_t row = 0; row < table.num_rows(); ++row) {
    const std::string& image = table.text(row, columns[0]);
    if (io::VnlogTable::is_missing(image)) continue;
    const double time = table.number(row, columns[1]);
    if (!std::isfinite(time))
      throw io::InputError(path, table.line(row),
                           "the timestamp of " + image + " is missing or not finite");
    const std::string name = fs::path(image).filename().string();
    if (name.empty() || name == "." || name == "..")
      throw io::InputError(path, table.line(row),
                           "image '" + image + "' names a folder, not an image file");
    if (!timestamps.emplace(name, ImageTimestamp{time, table.line(row)}).second)
      throw io::InputError(path, table.line(row), "image " + name + " is listed twice");
  }
  return timestamps;
}

void apply_timestamps(const std::map<std::string, ImageTimestamp>& timestamps,
                      const std::string& timestamps_file, std::vector<TrackedFrame>* frames) {
  const TrackedFrame* previous = nullptr;
  for (TrackedFrame& f : *frames) {
    const std::string name = fs::path(f.file).filename().string();
    const auto found = timestamps.find(name);
    if (f.file.empty() || found == timestamps.end())
      throw io::InputError(
          timestamps_file, 0,
          "has no timestamp for " +
              (f.file.empty() ? "video frame " + std::to_string(f.index) : "image " + name));
    f.timestamp = found->second.time;
    if (previous && !(f.timestamp > previous->timestamp))
      throw io::InputError(timestamps_file, found->second.line,
                           "image " + name + "'s time " + io::format_double(f.timestamp) +
                               " is not after that of the image before it, " +
                               fs::path(previous->file).filename().string() + " at " +
                               io::format_double(previous->timestamp) +
                               ": the images' times must increase in their order");
    previous = &f;
  }
}

}  // namespace omnisfm::track
