#pragma once
// The catadioptric model of each image in a rawlog: a CObservationOmniImage's own, else that of
// the last CObservationCameraModel seen under the image's sensorLabel (the stock images'
// carrier). Every reader of images (the replay, the track verb's reader, OmniSfmEstimator) keeps
// one as it goes through the observations.
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationImage.h>

#include <map>
#include <string>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"

namespace omnisfm::mrpt_plugin {

class ImageCameraModels {
 public:
  // Keeps the observation's model when it is a CObservationCameraModel; returns whether it was.
  bool note(const mrpt::obs::CObservation& observation);
  // Null when the image has no model.
  const CCatadioptricCameraModel* model_for(const mrpt::obs::CObservationImage& image) const;

 private:
  std::map<std::string, CCatadioptricCameraModel> by_label_;
};

}  // namespace omnisfm::mrpt_plugin
