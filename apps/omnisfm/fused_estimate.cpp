#include "fused_estimate.h"

namespace omnisfm::app {

// FUSION CALL SITE: once libs/sfm has sfm::run_fused_sfm, replace the body below with
//   return sfm::run_fused_sfm(camera, tracks, frame_timestamps, sensors, settings, progress);
// (including "omnisfm/sfm/fused_pipeline.h" or wherever it is declared) and make
// fusion_available() return true. Until then vision alone estimates, and the sensors are read,
// counted and reported but not used.
sfm::SfmResult estimate_fused(const camera::CatadioptricCamera& camera,
                              const std::vector<io::TrackObservation>& tracks,
                              const std::vector<double>& frame_timestamps,
                              const sfm::MotionSensors& sensors, const sfm::SfmSettings& settings,
                              const sfm::Progress& progress) {
  (void)frame_timestamps;
  (void)sensors;
  return sfm::run_sfm(camera, tracks, settings, progress);
}

bool fusion_available() { return false; }

}  // namespace omnisfm::app
