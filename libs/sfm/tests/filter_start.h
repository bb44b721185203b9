#pragma once
// The batch's start as the pipeline hands it over: the online filter on a simulated experiment,
// and the observations of the tracks it kept.

#include <set>
#include <string>
#include <vector>

#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {

struct FilterStart {
  sim::Dataset data;
  std::vector<core::TrackObservation> inliers;
  SfmResult online;
};

// Over the experiment's first `frames` frames (every frame when negative).
inline FilterStart filter_start(const std::string& scenario, std::uint64_t seed, int frames = -1) {
  sim::SimulationOptions options;
  options.scenario = scenario;
  options.seed = seed;
  FilterStart s{sim::simulate(options), {}, {}};
  if (frames >= 0) {
    std::vector<core::TrackObservation> kept;
    for (const auto& o : s.data.observations)
      if (o.frame < frames) kept.push_back(o);
    s.data.observations = kept;
    s.data.world_from_cam.resize(frames);
  }
  SfmSettings online;
  online.run_batch = false;
  s.online = run_sfm(s.data.camera, s.data.observations, online);
  std::set<int> outliers;
  for (const auto& o : s.online.outliers) outliers.insert(o.track);
  for (const auto& o : s.data.observations)
    if (!outliers.count(o.track)) s.inliers.push_back(o);
  return s;
}

}  // namespace omnisfm::sfm
