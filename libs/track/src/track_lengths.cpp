#include "omnisfm/track/track_lengths.h"

#include <algorithm>
#include <map>
#include <utility>

#include "omnisfm/core/percentile.h"

namespace omnisfm::track {

TrackLengths track_lengths(const std::vector<core::TrackObservation>& observations) {
  std::map<int, std::pair<int, int>> span;  // per track: first and last frame
  for (const auto& o : observations) {
    const auto [it, inserted] = span.try_emplace(o.track, o.frame, o.frame);
    if (inserted) continue;
    it->second.first = std::min(it->second.first, o.frame);
    it->second.second = std::max(it->second.second, o.frame);
  }
  std::vector<double> frames;
  frames.reserve(span.size());
  for (const auto& [track, first_last] : span)
    frames.push_back(first_last.second - first_last.first + 1);
  TrackLengths lengths;
  lengths.tracks = static_cast<int>(frames.size());
  if (frames.empty()) return lengths;
  lengths.median_frames = static_cast<int>(core::percentile(frames, 0.5));
  lengths.longest_frames = static_cast<int>(*std::max_element(frames.begin(), frames.end()));
  return lengths;
}

}  // namespace omnisfm::track
