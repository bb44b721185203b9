#pragma once
// CObservationTrackedFeatures: the features tracked in one image of an omnidirectional camera
// (each feature's track id and pixel), so that a rawlog can carry tracks without images. Pixels
// follow omnisfm's convention: (0, 0) is the centre of the top-left pixel. `frame` is the image's
// 0-based index, as in tracks.vnl; `sensorPose` is the camera frame C on the robot; `model` is
// the camera that saw the features (it may be empty when another observation carries it).
//
// Stream format, version 0:
//   timestamp, string sensorLabel
//   int32     frame
//   object    sensorPose (mrpt::poses::CPose3D)
//   object    model (CCatadioptricCameraModel)
//   uint32    number of features, then for each: int32 track, double u, double v
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <vector>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"

namespace omnisfm::mrpt_plugin {

struct TrackedFeature {
  int32_t track = 0;
  double u = 0, v = 0;
};

class CObservationTrackedFeatures : public mrpt::obs::CObservation {
  DEFINE_SERIALIZABLE(CObservationTrackedFeatures, omnisfm::mrpt_plugin)

 public:
  CObservationTrackedFeatures() = default;

  int32_t frame = 0;
  mrpt::poses::CPose3D sensorPose;
  CCatadioptricCameraModel model;
  std::vector<TrackedFeature> features;

  void getSensorPose(mrpt::poses::CPose3D& out_sensorPose) const override {
    out_sensorPose = sensorPose;
  }
  void setSensorPose(const mrpt::poses::CPose3D& newSensorPose) override {
    sensorPose = newSensorPose;
  }
  void getDescriptionAsText(std::ostream& o) const override;
};

}  // namespace omnisfm::mrpt_plugin
