#pragma once
// The estimators of `omnisfm run`: vision (the tracks and the frames' times) fused with the
// vehicle's own motion sensors. This is the one place the run verb calls the estimators.

#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::app {

// Throws what the estimators throw: std::invalid_argument for tracks that cannot support an
// estimate, std::runtime_error for degenerate motion.
sfm::SfmResult estimate_fused(const camera::CatadioptricCamera& camera,
                              const std::vector<io::TrackObservation>& tracks,
                              const std::vector<double>& frame_timestamps,
                              const sfm::MotionSensors& sensors, const sfm::SfmSettings& settings,
                              const sfm::Progress& progress);

// Whether estimate_fused uses the motion sensors (the report says so).
bool fusion_available();

}  // namespace omnisfm::app
