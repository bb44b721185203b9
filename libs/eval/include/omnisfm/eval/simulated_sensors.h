#pragma once
// The simulator's dead reckoning and GPS as the estimators take them (sfm::MotionSensors), with
// the noise models the simulation states: what a rawlog of the simulated vehicle would carry.

#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/gps_receiver.h"

namespace omnisfm::eval {

// Either may be null. The odometry's scale is taken as uncalibrated (1), known to 2 %.
sfm::MotionSensors motion_sensors(const sim::DeadReckoning* dead_reckoning,
                                  const sim::DeadReckoningOptions& dead_reckoning_options,
                                  const sim::GpsTrack* gps);

}  // namespace omnisfm::eval
