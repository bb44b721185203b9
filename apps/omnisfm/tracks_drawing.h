#pragma once
// A frame with its tracks drawn over it, for people to look at: each track seen in that frame as
// its path over its last frames and a dot where it is, coloured by how long it has lasted.

#include <opencv2/core.hpp>
#include <vector>

#include "omnisfm/core/track_observation.h"

namespace omnisfm::app {

// `grey` (CV_8UC1) in colour (CV_8UC3), with the tracks of `observations` (sorted by frame) seen
// in `frame`: their paths over the `trail` frames before it, blue for a track started there, red
// for one that has lasted `trail` frames or more.
cv::Mat draw_tracks(const cv::Mat& grey, const std::vector<core::TrackObservation>& observations,
                    int frame, int trail);

}  // namespace omnisfm::app
