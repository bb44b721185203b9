#pragma once
// CObservationCameraModel: a catadioptric camera's model and its pose on the robot, for the stock
// mrpt::obs::CObservationImage observations of the same sensorLabel that follow it in a rawlog.
// The images stay stock, so stock tools (RawLogViewer, `rawlog-edit --list-images`,
// `--externalize`) show and handle them; omnisfm's readers give each image the model most
// recently seen under its label (ImageCameraModels, rawlog_observations.h). Stock operations that
// keep a label's observations together keep the two in step (`--keep-label`, `--remove-label`,
// `--externalize`); those that change an image's pixels or lens (`--undistort`,
// `--camera-params`) or drop the model's entry (`--cut` past it) do not, and the README says so.
//
// Stream format, version 0:
//   timestamp, string sensorLabel
//   object    sensorPose (mrpt::poses::CPose3D): the camera frame C on the robot
//   object    model (CCatadioptricCameraModel)
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"

namespace omnisfm::mrpt_plugin {

class CObservationCameraModel : public mrpt::obs::CObservation {
  DEFINE_SERIALIZABLE(CObservationCameraModel, omnisfm::mrpt_plugin)

 public:
  CObservationCameraModel() = default;

  mrpt::poses::CPose3D sensorPose;
  CCatadioptricCameraModel model;

  void getSensorPose(mrpt::poses::CPose3D& out_sensorPose) const override {
    out_sensorPose = sensorPose;
  }
  void setSensorPose(const mrpt::poses::CPose3D& newSensorPose) override {
    sensorPose = newSensorPose;
  }
  void getDescriptionAsText(std::ostream& o) const override;
};

}  // namespace omnisfm::mrpt_plugin
