#include "omnisfm/sim/dataset_writer.h"


#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "omnisfm/io/atomic_write.h"
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
  io::write_folder_atomically(dir, [&](const std::string& folder) {
    write_contents(dataset, folder, write_image);
    if (write_more) write_more(folder);
  });
}

}  // namespace omnisfm::sim
