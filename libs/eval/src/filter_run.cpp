#include "omnisfm/eval/filter_run.h"

#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::eval {

void run_filter(const sim::Dataset& dataset, const sfm::MotionSensors* sensors,
                const sfm::FilterSettings& settings, sfm::OnlineFilter* filter,
                const std::function<void(int frame)>& after_frame) {
  const auto by_frame = sfm::observations_by_frame(dataset.observations);
  for (size_t f = 0; f < by_frame.size(); ++f) {
    const int frame = static_cast<int>(f);
    if (f == 0 || !sensors)
      filter->process_frame(frame, by_frame[f]);
    else
      filter->process_frame(frame, by_frame[f],
                            sfm::predict_camera_motion(*sensors, dataset.timestamps[f - 1],
                                                       dataset.timestamps[f], settings,
                                                       filter->sensor_states()));
    after_frame(frame);
  }
}

}  // namespace omnisfm::eval
