// Holds omnisfm's online estimator as MRPT's SLAM front end, a CMetricMapBuilder*, as an MRPT
// SLAM application would, and feeds it the simulated rover's tracked features as sensory frames.
// Exits 0 iff it processed every frame, kept keyframes and reports a finite Gaussian pose.

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/slam/CMetricMapBuilder.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"
#include "omnisfm/sim/scenario.h"

int main() {
  using namespace omnisfm;
  sim::SimulationOptions simulation;
  simulation.scenario = "rover";
  const sim::Dataset rover = sim::simulate(simulation);

  mrpt_plugin::OmniSfmEstimatorOptions options;
  options.camera = rover.camera;
  auto estimator = std::make_unique<mrpt_plugin::OmniSfmEstimator>(options);
  mrpt::slam::CMetricMapBuilder* builder = estimator.get();
  builder->initialize();
  for (size_t f = 0; f < rover.world_from_cam.size(); ++f) {
    auto features = std::make_shared<mrpt_plugin::CObservationTrackedFeatures>();
    features->sensorLabel = "OMNI_TRACKS";
    features->timestamp = mrpt::Clock::fromDouble(1e9 + 0.1 * static_cast<double>(f));
    features->frame = static_cast<int>(f);
    for (const auto& o : rover.observations)
      if (o.frame == static_cast<int>(f))
        features->features.push_back({o.track, o.pixel.x(), o.pixel.y()});
    mrpt::obs::CActionCollection no_motion;
    mrpt::obs::CSensoryFrame frame;
    frame.insert(features);
    builder->processActionObservation(no_motion, frame);
  }
  const auto pose = std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(
      builder->getCurrentPoseEstimation());
  const unsigned int keyframes = builder->getCurrentlyBuiltMapSize();
  if (estimator->framesProcessed() != static_cast<int>(rover.world_from_cam.size()) || !pose ||
      !std::isfinite(pose->mean.x()) || !std::isfinite(pose->cov(0, 0)) || keyframes < 2) {
    std::fprintf(stderr, "omnisfm_downstream_slam: the front end did not run (%d frames, %u "
                         "keyframes)\n", estimator->framesProcessed(), keyframes);
    return 1;
  }
  std::printf("%d frames, %u keyframes, robot at %.3f %.3f %.3f\n", estimator->framesProcessed(),
              keyframes, pose->mean.x(), pose->mean.y(), pose->mean.z());
  return 0;
}
