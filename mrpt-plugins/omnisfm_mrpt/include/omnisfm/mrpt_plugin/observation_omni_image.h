#pragma once
// CObservationOmniImage: an image from a catadioptric omnidirectional camera with the camera's
// model and its pose on the robot. It is an mrpt::obs::CObservationImage, so stock MRPT tools
// handle its `image`, `cameraPose` (the camera frame C on the robot: x right, y down, z toward the
// mirror) and `timestamp` as they do any camera's. Its `cameraParams` describe only the inner
// camera's lens (the pinhole's intrinsics and distortion; just the image size for other inner
// cameras), not the mirror: geometry goes through `model`.
//
// Stream format, version 0:
//   uint8     the CObservationImage format's version, then that format (MRPT's own writer)
//   object    the CCatadioptricCameraModel, with its own class name and version
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/obs/CObservationImage.h>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"

namespace omnisfm::mrpt_plugin {

class CObservationOmniImage : public mrpt::obs::CObservationImage {
  DEFINE_SERIALIZABLE(CObservationOmniImage, omnisfm::mrpt_plugin)

 public:
  CObservationOmniImage() = default;

  CCatadioptricCameraModel model;

  // Sets `model` and fills `cameraParams` from the inner camera.
  void set_camera(const camera::CatadioptricCamera& camera);

  void getDescriptionAsText(std::ostream& o) const override;
};

// The inner camera's intrinsics as MRPT's TCamera: a pinhole's fx fy cx cy and k1 k2 p1 p2 k3;
// only the image size for orthographic and mrcal inner cameras.
mrpt::img::TCamera inner_camera_params(const camera::CatadioptricCamera& camera);

}  // namespace omnisfm::mrpt_plugin
