#include "omnisfm/mrpt_plugin/image_camera_models.h"

#include "omnisfm/mrpt_plugin/observation_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"

namespace omnisfm::mrpt_plugin {

bool ImageCameraModels::note(const mrpt::obs::CObservation& observation) {
  const auto* model = dynamic_cast<const CObservationCameraModel*>(&observation);
  if (!model) return false;
  by_label_[model->sensorLabel] = model->model;
  return true;
}

const CCatadioptricCameraModel* ImageCameraModels::model_for(
    const mrpt::obs::CObservationImage& image) const {
  if (const auto* omni = dynamic_cast<const CObservationOmniImage*>(&image))
    return omni->model.has_camera() ? &omni->model : nullptr;
  const auto model = by_label_.find(image.sensorLabel);
  return model != by_label_.end() && model->second.has_camera() ? &model->second : nullptr;
}

}  // namespace omnisfm::mrpt_plugin
