#pragma once
// How long tracks last: the frames each spans, from its first observation to its last (gaps
// where it was lost and reacquired included). Long tracks carry the parallax that fixes their
// points; a tracker that ends them early costs the filter a new point each.

#include <vector>

#include "omnisfm/core/track_observation.h"

namespace omnisfm::track {

struct TrackLengths {
  int tracks = 0;
  int median_frames = 0;  // core::percentile's median (the upper middle one for an even count)
  int longest_frames = 0;
};

TrackLengths track_lengths(const std::vector<core::TrackObservation>& observations);

}  // namespace omnisfm::track
