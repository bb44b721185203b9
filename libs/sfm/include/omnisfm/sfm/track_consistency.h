#pragma once
// The batch's whole-track test. A track that drifts slowly off its point stays within a pixel's
// limit at every frame (the point it is triangulated to follows it halfway), but not within the
// noise over its length. Each track's squared residuals are summed and tested against
// chi-square with 2n - 3 degrees of freedom (n sightings, 3 taken by its point), at the stated
// pixel noise, or at the tracks' own where the median track's is larger (a noise understated, or
// a camera a little off, raises every track's residuals together and rejects none for it). Not
// below the stated noise: a real tracker's tracks differ in noise with their contrast, and the
// best half of them would make the rest look like drifts.

#include <cmath>
#include <map>

namespace omnisfm::sfm {

// One track's residuals against a solution.
struct TrackResidualSum {
  int sightings = 0;
  double squared_px2 = 0;  // sum of the residuals' squared norms
  int worst_frame = -1;    // where its residual is largest
  double worst_px = 0;
  void add(int frame, double residual_px);
};

struct InconsistentTracks {
  // The tracks' own noise per coordinate, from the median track; NaN when too few tracks (fewer
  // than 5 of 3 or more sightings) tell it.
  double measured_noise_px = NAN;
  double noise_px = NAN;  // the noise the test took
  std::map<int, int> tracks;  // rejected track -> the frame of its largest residual
};

// The tracks whose residuals a good track would exceed with probability `false_alarm` (0 < it <
// 1), at `stated_noise_px` per coordinate (> 0) or the tracks' own noise where larger.
InconsistentTracks inconsistent_tracks(const std::map<int, TrackResidualSum>& sums,
                                       double false_alarm, double stated_noise_px);

// Whether one track's residuals are beyond what a good track reaches with probability
// `false_alarm` at `noise_px` per coordinate (false for a track of one sighting).
bool exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double false_alarm);

}  // namespace omnisfm::sfm
