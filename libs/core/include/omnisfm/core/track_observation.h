#pragma once
// One observation of a tracked feature: the track's pixel in a frame. What the tracker gives, the
// simulator makes, the estimators take and tracks.vnl holds.

#include <Eigen/Core>

namespace omnisfm::core {

struct TrackObservation {
  int frame = 0;
  int track = 0;
  Eigen::Vector2d pixel{0, 0};  // (0, 0) the centre of the top-left pixel
};

}  // namespace omnisfm::core
