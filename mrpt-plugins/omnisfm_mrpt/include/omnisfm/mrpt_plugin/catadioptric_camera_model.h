#pragma once
// CCatadioptricCameraModel: an omnisfm catadioptric camera (camera::CatadioptricCamera) as an MRPT
// serializable object, registered as "omnisfm::mrpt_plugin::CCatadioptricCameraModel". It holds
// every parameter, so a rawlog needs no camera file: the inner camera (pinhole with OpenCV
// distortion, orthographic, or any mrcal lens model by name and intrinsics), the mirror (an
// equiangular, conic or tabulated profile with its valid range) and the 5-DOF mirror pose.
//
// Stream format, version 0 (a later version keeps a reader for it):
//   bool      has_camera; when false nothing follows
//   int32     image_width, image_height
//   string    inner kind: "pinhole" | "orthographic" | "mrcal"
//   double[]  inner parameters, in InnerCamera::params() order
//   (mrcal)   string lens model name, e.g. "LENSMODEL_OPENCV8"; int32 imager width, height
//   string    mirror kind: "equiangular" | "conic" | "table"
//   double[]  shape parameters, in MirrorProfile::shape_params() order
//   double    valid range s_min, s_max
//   (table)   double[] rho samples, double[] z samples
//   double    mirror pose rx ry tx ty tz
// A stored model that does not make a valid camera throws std::runtime_error when read.
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/serialization/CSerializable.h>

#include <iosfwd>
#include <optional>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::mrpt_plugin {

class CCatadioptricCameraModel : public mrpt::serialization::CSerializable {
  DEFINE_SERIALIZABLE(CCatadioptricCameraModel, omnisfm::mrpt_plugin)

 public:
  // Empty (no camera), as MRPT's class factory builds objects before reading them.
  CCatadioptricCameraModel() = default;
  explicit CCatadioptricCameraModel(camera::CatadioptricCamera camera);

  bool has_camera() const { return camera_.has_value(); }
  // Throws std::logic_error when the model is empty.
  const camera::CatadioptricCamera& camera() const;
  void set_camera(camera::CatadioptricCamera camera) { camera_ = std::move(camera); }

  // Several lines: the kinds, the image size and every named parameter.
  void getDescriptionAsText(std::ostream& o) const;

 private:
  std::optional<camera::CatadioptricCamera> camera_;
};

}  // namespace omnisfm::mrpt_plugin
