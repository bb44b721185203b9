#pragma once
// How closely image tracks follow the scene, on a simulated dataset whose scene and poses are
// known. A tracker picks its own features, so a track's true point is where the reflected ray of
// its first observation meets the scene; its true pixel in a later frame is that point's
// projection, when the rig sees it there.

#include <vector>

#include "omnisfm/core/track_observation.h"
#include "omnisfm/sim/dataset.h"

namespace omnisfm::eval {

// Per observation, in the order given: the distance in pixels from its true pixel; NaN for a
// track's first observation (the truth is defined by it) and for every observation of a track
// whose first ray meets nothing; +infinity where the true point is hidden or out of view.
std::vector<double> track_errors(const sim::Dataset& dataset,
                                 const std::vector<core::TrackObservation>& tracks);

struct TrackAccuracy {
  int tracks = 0;             // whose first ray meets the scene
  int unanchored_tracks = 0;  // whose first ray meets nothing (sky)
  // Tracks with an observation farther than the threshold from the truth, or where the point is
  // hidden: the tracker followed something else.
  int mistracked_tracks = 0;
  std::vector<int> mistracked;
  // Over the later observations (first ones excluded) of the tracks that follow their point.
  int observations = 0;
  double median_px = 0, p95_px = 0, max_px = 0;
  // Later observations, in all tracks, beyond the threshold or hidden.
  int mistracked_observations = 0;
  int all_observations = 0;
  // Reacquisitions: observations that follow a gap in their track, and how many of them are
  // beyond the threshold or hidden (the track came back on something else).
  int reacquisitions = 0;
  int wrong_reacquisitions = 0;
};

// `tracks` sorted by frame, as tracks.vnl is.
TrackAccuracy track_accuracy(const sim::Dataset& dataset,
                             const std::vector<core::TrackObservation>& tracks,
                             double mistrack_threshold_px = 1.0);

}  // namespace omnisfm::eval
