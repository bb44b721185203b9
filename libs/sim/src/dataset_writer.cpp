#include "omnisfm/sim/dataset_writer.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::sim {
namespace fs = std::filesystem;
namespace {

void write_table(const fs::path& path, const std::vector<std::string>& columns,
                 const std::function<void(io::VnlogWriter&)>& rows) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
  io::VnlogWriter writer(out, columns);
  rows(writer);
  out.flush();
  if (!out) throw std::runtime_error(path.string() + ": write failed");
}

void write_contents(const Dataset& d, const fs::path& dir, const FrameImageWriter& write_image) {
  io::write_camera_file((dir / "camera.ini").string(), d.camera);

  write_table(dir / "tracks.vnl", {"frame", "track", "u", "v"}, [&](io::VnlogWriter& w) {
    for (const auto& o : d.observations)
      w.row({double(o.frame), double(o.track), o.pixel.x(), o.pixel.y()});
  });

  const int frames = static_cast<int>(d.world_from_cam.size());
  std::vector<std::string> image_names(frames, "-");
  if (write_image) {
    fs::create_directory(dir / "images");
    for (int f = 0; f < frames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "images/%06d.png", f);
      write_image(f, (dir / name).string());
      image_names[f] = name;
    }
  }
  write_table(dir / "frames.vnl", {"frame", "timestamp", "image"}, [&](io::VnlogWriter& w) {
    for (int f = 0; f < frames; ++f)
      w.row_texts({std::to_string(f), io::VnlogWriter::field(d.timestamps[f]), image_names[f]});
  });

  std::vector<io::StampedPose> truth(frames);
  for (int f = 0; f < frames; ++f) truth[f] = {d.timestamps[f], d.world_from_cam[f]};
  io::write_tum_trajectory((dir / "ground_truth.tum").string(), truth);

  write_table(dir / "points_gt.vnl", {"track", "x", "y", "z"}, [&](io::VnlogWriter& w) {
    for (size_t t = 0; t < d.track_points.size(); ++t) {
      const auto& p = d.track_points[t];
      w.row({double(t), p.x(), p.y(), p.z()});
    }
  });
  write_table(dir / "outliers_gt.vnl", {"track", "frame"}, [&](io::VnlogWriter& w) {
    for (const auto& o : d.outliers) w.row({double(o.track), double(o.frame)});
  });

  if (!d.surveyed_targets.empty()) {
    write_table(dir / "targets.vnl", {"target", "x", "y", "z"}, [&](io::VnlogWriter& w) {
      for (size_t t = 0; t < d.surveyed_targets.size(); ++t) {
        const auto& p = d.surveyed_targets[t];
        w.row({double(t), p.x(), p.y(), p.z()});
      }
    });
    write_table(dir / "observations.vnl", {"image", "target", "u", "v"}, [&](io::VnlogWriter& w) {
      for (const auto& o : d.target_observations)
        w.row({double(o.image), double(o.target), o.pixel.x(), o.pixel.y()});
    });
  }
}

}  // namespace

void write_dataset(const Dataset& dataset, const std::string& dir,
                   const FrameImageWriter& write_image, const FolderWriter& write_more) {
  const fs::path target = fs::absolute(dir).lexically_normal();
  const fs::path parent = target.parent_path();
  const std::string stem = target.filename().string();
  std::error_code ec;
  if (!fs::is_directory(parent, ec))
    throw std::runtime_error(dir + ": the folder " + parent.string() + " does not exist");
  if (fs::exists(target, ec) && !fs::is_directory(target, ec))
    throw std::runtime_error(dir + ": exists and is not a folder");

  const std::string suffix = std::to_string(::getpid());
  const fs::path partial = parent / ("." + stem + ".partial-" + suffix);
  const fs::path previous = parent / ("." + stem + ".previous-" + suffix);
  fs::remove_all(partial, ec);
  if (!fs::create_directory(partial, ec))
    throw std::runtime_error(dir + ": cannot create a folder in " + parent.string() + ": " +
                             ec.message());
  try {
    write_contents(dataset, partial, write_image);
    if (write_more) write_more(partial.string());
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
  // Swap the finished folder into place; the old one goes only once the new one is there.
  const bool replacing = fs::exists(target, ec);
  if (replacing) fs::rename(target, previous, ec);
  if (ec || (fs::rename(partial, target, ec), ec)) {
    const std::string why = ec.message();
    if (replacing && !fs::exists(target)) fs::rename(previous, target, ec);
    fs::remove_all(partial, ec);
    throw std::runtime_error(dir + ": cannot move the dataset into place: " + why);
  }
  if (replacing) fs::remove_all(previous, ec);
}

}  // namespace omnisfm::sim
