#include "omnisfm/mrpt_plugin/rawlog_input.h"

#include <mrpt/obs/CObservationImage.h>

#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "rawlog_observations.h"

namespace omnisfm::mrpt_plugin {

RawlogReadResult for_each_rawlog_image(const std::string& path,
                                       const std::function<void(RawlogImage&)>& visit,
                                       const std::string& sensor_label) {
  use_external_images_of(path);
  RawlogReader reader(path);
  RawlogReadResult result;
  ImageCameraModels models;
  while (const auto object = reader.next()) {
    const std::size_t index = reader.index() - 1;
    std::string damage;
    for_each_observation(object, [&](const mrpt::obs::CObservation::Ptr& observation) {
      if (models.note(*observation)) return;
      const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(observation);
      if (!image || !damage.empty() || !has_label(*image, sensor_label)) return;
      std::optional<RawlogImage> loaded = load_rawlog_image(*image, index, models, &damage);
      if (!loaded) return;
      visit(*loaded);
      ++result.used;
    });
    if (!damage.empty()) {
      result.objects = index;
      result.problem = damage;
      return result;
    }
  }
  result.objects = reader.index();
  result.problem = reader.problem();
  return result;
}

RawlogReadResult read_rawlog_tracks(const std::string& path, RawlogTracks* tracks,
                                    const std::string& sensor_label) {
  RawlogReader reader(path);
  RawlogReadResult result;
  while (const auto object = reader.next()) {
    for_each_observation(object, [&](const mrpt::obs::CObservation::Ptr& observation) {
      const auto features = std::dynamic_pointer_cast<CObservationTrackedFeatures>(observation);
      if (!features || !has_label(*features, sensor_label)) return;
      tracks->frames.push_back({features->frame, mrpt::Clock::toDouble(features->timestamp)});
      append_tracked_features(*features, features->frame, &tracks->observations);
      if (!tracks->camera && features->model.has_camera())
        tracks->camera = features->model.camera();
      ++result.used;
    });
  }
  result.objects = reader.index();
  result.problem = reader.problem();
  return result;
}

}  // namespace omnisfm::mrpt_plugin
