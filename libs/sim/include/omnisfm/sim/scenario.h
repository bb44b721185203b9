#pragma once
// The paper's three experiments, simulated:
//   lab:   a calibrated imaging lab; 44 surveyed targets on the walls and ceiling; the rig (mirror
//          below the camera, looking up) moves without rotating in a U along three edges of an
//          optical bench: 41 images, 4.08 m.
//   crane: the Robocrane; 140 images on a horizontal circular arc, 3.08 m, pitch and roll keeping
//          the rig's axis on one ground point; 32 tracked points, 10 of them mistracked part way.
//   rover: a ground rover; planar motion with yaw changes, 150 images, 3.91 m; 112 points, 7 of
//          them outliers.
//   drive: a rover drive of any length (endless_drive.h): `frames` frames 3 cm apart, about 30
//          live tracks, no outliers.

#include <cstdint>
#include <string>

#include "omnisfm/sim/dataset.h"

namespace omnisfm::sim {

struct SimulationOptions {
  std::string scenario = "lab";  // lab | crane | rover | drive
  std::uint64_t seed = 1;
  double tracking_noise_px = 0.2;  // Gaussian, per pixel coordinate
  double survey_error_m = 0.0;     // Gaussian, per target coordinate (lab)
  int image_width = 1024, image_height = 768;
  int frames = 20000;  // drive only
};

// The names simulate() accepts.
bool is_known_scenario(const std::string& name);

// Deterministic for given options. Throws std::invalid_argument for an unknown scenario or
// nonsense options (negative noise, image too small).
Dataset simulate(const SimulationOptions& options);

// The default rig: an equiangular mirror with a small, realistic misalignment (a few mm, a few
// tenths of a degree) on a pinhole camera, scaled to the image size.
camera::CatadioptricCamera default_rig(int image_width, int image_height);

}  // namespace omnisfm::sim
