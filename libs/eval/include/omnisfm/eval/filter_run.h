#pragma once
// The online filter over a simulated dataset, frame by frame, as sfm::run_fused_sfm feeds it:
// the first frame as it is, each later one propagated by the vehicle's sensors' prediction, or by
// the random walk without sensors. The studies of its consistency and drift look at it after each
// frame.

#include <functional>

#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sim/dataset.h"

namespace omnisfm::eval {

// `filter` made by the caller (with its settings, and a linearisation to study if any);
// `settings` those it was made with, which the prediction reads; `sensors` may be null. Calls
// after_frame(f) once frame f is processed.
void run_filter(const sim::Dataset& dataset, const sfm::MotionSensors* sensors,
                const sfm::FilterSettings& settings, sfm::OnlineFilter* filter,
                const std::function<void(int frame)>& after_frame);

}  // namespace omnisfm::eval
