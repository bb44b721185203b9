#pragma once
// What each of the motion sensors' numbers can mean: its [run] key, its range and why values
// beyond say nothing (a noise numerically zero, a wheel a factor of ten off). One table for the
// [run] reader (mrpt_plugin::read_run_options), which fails at the key's line, and for sensors
// set in code (sensors_problem), which run_fused_sfm and OmniSfmEstimator refuse.

#include <string>
#include <vector>

#include "omnisfm/sfm/motion_sensors.h"

namespace omnisfm::sfm {

struct SensorRange {
  const char* key;  // the [run] key
  double low, high;
  const char* meaning;
  double& (*field)(MotionSensors&);
};

// The odometry's numbers, then the gyro's.
const std::vector<SensorRange>& sensor_ranges();

// "" when every number is within what it can mean, else the first that is not: "KEY = VALUE
// must be ...: MEANING".
std::string sensors_problem(const MotionSensors& sensors);

}  // namespace omnisfm::sfm
