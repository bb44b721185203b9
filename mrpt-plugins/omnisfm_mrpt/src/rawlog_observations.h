#pragma once
// How the rawlog readers take MRPT observations apart: shared by the image and track readers
// (rawlog_input.h) and the replay (rawlog_replay_input.h), which reads everything in one pass.

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "omnisfm/io/tracks_file.h"
#include "omnisfm/mrpt_plugin/image_camera_models.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_input.h"

namespace omnisfm::mrpt_plugin {

// An observation object is itself; a sensory frame holds several; actions hold none.
void for_each_observation(const mrpt::serialization::CSerializable::Ptr& object,
                          const std::function<void(const mrpt::obs::CObservation::Ptr&)>& visit);

// The image observation (the rawlog's object `index`), its image loaded and made grey, its camera
// from `models`; empty, with *damage saying why (describe_damage's wording), when the image cannot
// be loaded.
std::optional<RawlogImage> load_rawlog_image(mrpt::obs::CObservationImage& image,
                                             std::size_t index, const ImageCameraModels& models,
                                             std::string* damage);

// The frame's features as observations of frame number `frame`, appended to *observations.
void append_tracked_features(const CObservationTrackedFeatures& features, int frame,
                             std::vector<core::TrackObservation>* observations);

// True for every observation when `label` is empty.
bool has_label(const mrpt::obs::CObservation& observation, const std::string& label);

}  // namespace omnisfm::mrpt_plugin
