#include "omnisfm/sfm/track_consistency.h"

#include <algorithm>
#include <vector>

#include "omnisfm/core/chi_square.h"
#include "omnisfm/core/percentile.h"

namespace omnisfm::sfm {
namespace {

constexpr int kMinTracksForNoise = 5;

double track_degrees_of_freedom(const TrackResidualSum& s) { return 2.0 * s.sightings - 3; }

}  // namespace

void TrackResidualSum::add(int frame, double residual_px) {
  ++sightings;
  squared_px2 += residual_px * residual_px;
  if (worst_frame < 0 || residual_px > worst_px) {
    worst_frame = frame;
    worst_px = residual_px;
  }
}

InconsistentTracks inconsistent_tracks(const std::map<int, TrackResidualSum>& sums,
                                       double false_alarm, double stated_noise_px) {
  // Each track's variance per coordinate, over the median a chi-square of its degrees of freedom
  // takes (Wilson-Hilferty: dof (1 - 2 / (9 dof))^3), so that short tracks do not pull the noise
  // below what the long ones show.
  std::vector<double> variances;
  for (const auto& [track, s] : sums) {
    const double dof = track_degrees_of_freedom(s);
    if (dof < 3) continue;
    const double median_fraction = std::pow(1 - 2 / (9 * dof), 3);
    variances.push_back(s.squared_px2 / dof / median_fraction);
  }
  InconsistentTracks result;
  double variance = stated_noise_px * stated_noise_px;
  if (static_cast<int>(variances.size()) >= kMinTracksForNoise) {
    // The lower median, index (n - 1) / 2: with an even count, the better of the two middle tracks.
    const double measured = core::percentile(variances, 0.5 - 0.5 / variances.size());
    result.measured_noise_px = std::sqrt(measured);
    variance = std::max(variance, measured);
  }
  if (!(variance > 0)) return result;
  result.noise_px = std::sqrt(variance);
  for (const auto& [track, s] : sums)
    if (exceeds_its_noise(s, result.noise_px, false_alarm)) result.tracks[track] = s.worst_frame;
  return result;
}

bool exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double false_alarm) {
  const double dof = track_degrees_of_freedom(sum);
  return dof >= 1 && sum.squared_px2 / (noise_px * noise_px) >
                         core::chi_square_upper_quantile(dof, false_alarm);
}

}  // namespace omnisfm::sfm
