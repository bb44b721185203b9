#pragma once
// A long drive for the batch adjustment's scaling: `images` frames of the rover's rig 3 cm apart
// along an S that repeats every 300 frames, one ground point per frame a little to the side of
// the path, seen from the frames within 15 of its own that image it (tracks about 30 images
// long), pixels with Gaussian noise. Frames share points with their neighbours only, so the
// reduced camera system of a Schur solver is banded.

#include <cstdint>

#include "omnisfm/sim/dataset.h"

namespace omnisfm::sim {

// world_from_cam, track_points and observations filled; no timestamps, outliers or scene.
Dataset long_drive(int images, double pixel_noise, std::uint64_t seed);

}  // namespace omnisfm::sim
