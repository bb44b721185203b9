#pragma once
// The batch's whole-track test. A track that drifts slowly off its point stays within a pixel's
// limit at every frame (the point it is triangulated to follows it halfway), but not within the
// noise over its length. Each track's squared residuals are summed and tested against
// chi-square with 2n - 3 degrees of freedom (n sightings, 3 taken by its point), at the stated
// pixel noise, or at the tracks' own where the median track's is larger (a noise understated, or
// a camera a little off, raises every track's residuals together and rejects none for it). Not
// below the stated noise: a real tracker's tracks differ in noise with their contrast, and the
// best half of them would make the rest look like drifts.
//
// A drift's residuals are also ordered: they grow from the frame it starts. The sum spreads them
// over all 2n - 3 degrees of freedom; a ramp from each frame on, fitted to the residuals together
// with a move of the point (which takes part of any drift), puts them in 2 and catches drifts too
// slow for the sum (a generalised likelihood ratio, its false alarm shared among the frames it
// may start at). A camera a little off makes the residuals of the tracks where its error is
// largest smooth, as a drift's, so the ramp's noise is also measured from the tracks: from the
// 90th percentile of the tracks' whole-length ramps (with 20 tracks or more), which leaves room
// for about a tenth of them to drift.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <map>
#include <vector>

namespace omnisfm::sfm {

// One track's residuals against a solution.
struct TrackResidualSum {
  int sightings = 0;
  double squared_px2 = 0;  // sum of the residuals' squared norms
  int worst_frame = -1;    // where its residual is largest
  double worst_px = 0;
  std::vector<int> frames;  // increasing, whatever the order added
  std::vector<Eigen::Vector2d> residuals_px;
  // The pixel's derivative by the point, per sighting (every sighting added with one, or none);
  // without them the ramp is fitted alone.
  std::vector<Eigen::Matrix<double, 2, 3>> point_jacobians;
  void add(int frame, const Eigen::Vector2d& residual_px);
  void add(int frame, const Eigen::Vector2d& residual_px,
           const Eigen::Matrix<double, 2, 3>& point_jacobian);

 private:
  std::ptrdiff_t insert(int frame, const Eigen::Vector2d& residual_px);  // where it went
};

struct InconsistentTracks {
  // The tracks' own noise per coordinate, from the median track; NaN when too few tracks (fewer
  // than 5 of 3 or more sightings) tell it.
  double measured_noise_px = NAN;
  double noise_px = NAN;       // the noise the sum's test took
  double ramp_noise_px = NAN;  // and the ramp's: the sum's, or the tracks' ramps' where larger
  std::map<int, int> tracks;  // rejected track -> the frame of its largest residual
};

// The tracks' own noise per coordinate, from the median track (its squared residuals over the
// median of a chi-square of its degrees of freedom); NaN when fewer than 5 tracks of 3 or more
// sightings tell it.
double measured_track_noise_px(const std::map<int, TrackResidualSum>& sums);

// The tracks whose residuals a good track would exceed with probability `false_alarm` (0 < it <
// 1), at `stated_noise_px` per coordinate (> 0) or the tracks' own noise where larger.
InconsistentTracks inconsistent_tracks(const std::map<int, TrackResidualSum>& sums,
                                       double false_alarm, double stated_noise_px);

// Whether one track's residuals are beyond what a good track reaches with probability
// `false_alarm` (shared between the two tests below) at `noise_px` per coordinate in their sum,
// or at `ramp_noise_px` as a ramp (false for a track of one sighting).
bool exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double ramp_noise_px,
                       double false_alarm);

// The sum's test alone: chi-square with 2n - 3 degrees of freedom, exceeded with probability
// `false_alarm` by a good track.
bool sum_exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double false_alarm);

// The ramp's test alone: exceeded by a good track with probability at most `false_alarm`.
bool ramp_exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double false_alarm);

// The largest ramp statistic (in units of its variance) a good track exceeds with probability at
// most `false_alarm`.
double ramp_limit(const TrackResidualSum& sum, double false_alarm);

// The ramp's statistic from each sighting on, at a noise of 1 (0 where it tells nothing).
std::vector<double> ramp_statistics(const TrackResidualSum& sum);

// The largest, over the sightings a drift may start at, of the squared norm of the ramp fitted
// to the residuals from there on, in units of its own variance at `noise_px` (chi-square with 2
// degrees of freedom for each start of a good track's white residuals). With the point's
// Jacobians, the ramp's variance is what is left of it beside a move of the point.
double largest_ramp_statistic(const TrackResidualSum& sum, double noise_px);

}  // namespace omnisfm::sfm
