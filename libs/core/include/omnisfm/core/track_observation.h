#pragma once
// A tracked feature's pixel: in the frame at hand (what the tracker gives for each image and the
// online filter takes), or in a given frame (what the simulator makes, the batch takes and
// tracks.vnl holds).

#include <Eigen/Core>

namespace omnisfm::core {

struct TrackPixel {
  int track = 0;
  Eigen::Vector2d pixel{0, 0};  // (0, 0) the centre of the top-left pixel
};

struct TrackObservation {
  int frame = 0;
  int track = 0;
  Eigen::Vector2d pixel{0, 0};  // (0, 0) the centre of the top-left pixel
};

}  // namespace omnisfm::core
