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
// Stock tools: `rawlog-edit --export-txt` writes one row per frame (exportTxtDataRow), and a 3D
// view of the observation (getVisualizationInto) shows each feature's ray off the mirror.
//
// MRPT headers: the including target must link MRPT (mrpt::obs, mrpt::opengl) itself.

#include <mrpt/obs/CObservation.h>
#include <mrpt/opengl/Visualizable.h>
#include <mrpt/poses/CPose3D.h>

#include <cstdint>
#include <string>
#include <vector>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"

namespace omnisfm::mrpt_plugin {

struct TrackedFeature {
  int32_t track = 0;
  double u = 0, v = 0;
};

class CObservationTrackedFeatures : public mrpt::obs::CObservation,
                                    public mrpt::opengl::Visualizable {
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

  // A row holds the frame, the number of features, then each feature's track, u and v: rows are
  // as long as their frame has features. MRPT puts the timestamp first.
  bool exportTxtSupported() const override { return true; }
  std::string exportTxtHeader() const override;
  std::string exportTxtDataRow() const override;

  // Each feature's ray, from where it leaves the mirror, kVisualizedRayLength long, in the robot
  // frame (through sensorPose). Nothing without a model, nor for a pixel the model cannot
  // unproject.
  static constexpr double kVisualizedRayLength = 2.0;  // metres
  void getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const override;
};

}  // namespace omnisfm::mrpt_plugin
