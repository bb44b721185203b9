#pragma once
// The order camera frames come in: each later than the last. Two frames at one time would be one
// pose twice in a trajectory, and the TUM files (and eval) pair poses by time.

#include <mrpt/core/Clock.h>
#include <mrpt/system/datetime.h>

#include <string>

#include "omnisfm/io/number_text.h"

namespace omnisfm::mrpt_plugin {

// Why a camera frame at `time` (s) cannot follow one at `last`, or "".
inline std::string frame_time_problem(double time, double last) {
  if (time > last) return "";
  if (time == mrpt::Clock::toDouble(INVALID_TIMESTAMP))
    return "a camera frame without a time (INVALID_TIMESTAMP): each camera frame needs its own, "
           "later than the last";
  if (time == last)
    return "a camera frame at " + io::format_double(time) +
           " s, the time of the one before: two frames cannot share a time (the trajectory files "
           "pair poses by time)";
  return "a camera frame at " + io::format_double(time) + " s after one at " +
         io::format_double(last) + " s: the observations are out of time order";
}

}  // namespace omnisfm::mrpt_plugin
