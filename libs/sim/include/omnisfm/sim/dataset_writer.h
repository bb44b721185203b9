#pragma once
// Writes a simulated dataset as DESIGN.md's files: camera.ini, tracks.vnl, frames.vnl,
// ground_truth.tum, points_gt.vnl, outliers_gt.vnl, and for the lab targets.vnl and
// observations.vnl; with images, images/NNNNNN.png listed in frames.vnl.

#include <functional>
#include <string>

#include "omnisfm/sim/dataset.h"

namespace omnisfm::sim {

// Writes the image of `frame` to `path` (a PNG); throws on failure.
using FrameImageWriter = std::function<void(int frame, const std::string& path)>;
// Writes further files into the dataset's folder (given as a path), after the others.
using FolderWriter = std::function<void(const std::string& dir)>;

// Everything is written into a temporary folder beside `dir` and moved into place only when
// complete (io::write_folder_atomically), so a failure or a kill never leaves a dataset that
// looks whole; an existing `dir` is replaced.
// Throws std::runtime_error naming the folder when it cannot be written.
void write_dataset(const Dataset& dataset, const std::string& dir,
                   const FrameImageWriter& write_image = nullptr,
                   const FolderWriter& write_more = nullptr);

}  // namespace omnisfm::sim
