#include "omnisfm/eval/track_accuracy.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "omnisfm/core/percentile.h"
#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::eval {

std::vector<double> track_errors(const sim::Dataset& dataset,
                                 const std::vector<core::TrackObservation>& tracks) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Each track's first observation, then its true point (or none).
  std::map<int, size_t> first;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const auto at = first.find(tracks[i].track);
    if (at == first.end() || tracks[i].frame < tracks[at->second].frame) first[tracks[i].track] = i;
  }
  std::map<int, Eigen::Vector3d> truth;
  for (const auto& [track, index] : first) {
    const core::TrackObservation& o = tracks[index];
    Eigen::Vector3d point;
    if (sim::scene_point(dataset, o.frame, o.pixel, &point)) truth[track] = point;
  }

  std::vector<double> errors(tracks.size(), nan);
  for (size_t i = 0; i < tracks.size(); ++i) {
    const core::TrackObservation& o = tracks[i];
    const auto point = truth.find(o.track);
    if (point == truth.end() || first[o.track] == i) continue;
    Eigen::Vector2d pixel;
    errors[i] = sim::true_pixel(dataset, o.frame, point->second, &pixel)
                    ? (pixel - o.pixel).norm()
                    : std::numeric_limits<double>::infinity();
  }
  return errors;
}

TrackAccuracy track_accuracy(const sim::Dataset& dataset,
                             const std::vector<core::TrackObservation>& tracks,
                             double mistrack_threshold_px) {
  const std::vector<double> errors = track_errors(dataset, tracks);
  std::set<int> all_tracks, anchored, mistracked;
  for (size_t i = 0; i < tracks.size(); ++i) {
    all_tracks.insert(tracks[i].track);
    if (std::isnan(errors[i])) continue;
    anchored.insert(tracks[i].track);
    if (!(errors[i] <= mistrack_threshold_px)) mistracked.insert(tracks[i].track);
  }
  TrackAccuracy a;
  std::vector<double> followed;
  std::map<int, int> last_frame;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const auto previous = last_frame.find(tracks[i].track);
    const bool after_gap = previous != last_frame.end() && tracks[i].frame > previous->second + 1;
    last_frame[tracks[i].track] = tracks[i].frame;
    if (std::isnan(errors[i])) continue;
    if (after_gap) {
      ++a.reacquisitions;
      if (!(errors[i] <= mistrack_threshold_px)) ++a.wrong_reacquisitions;
    }
    ++a.all_observations;
    if (!(errors[i] <= mistrack_threshold_px)) ++a.mistracked_observations;
    if (!mistracked.count(tracks[i].track)) followed.push_back(errors[i]);
  }
  a.tracks = static_cast<int>(anchored.size());
  a.unanchored_tracks = static_cast<int>(all_tracks.size() - anchored.size());
  a.mistracked_tracks = static_cast<int>(mistracked.size());
  a.mistracked.assign(mistracked.begin(), mistracked.end());
  a.observations = static_cast<int>(followed.size());
  a.median_px = core::percentile(followed, 0.5);
  a.p95_px = core::percentile(followed, 0.95);
  a.max_px = followed.empty() ? 0 : *std::max_element(followed.begin(), followed.end());
  return a;
}

}  // namespace omnisfm::eval
