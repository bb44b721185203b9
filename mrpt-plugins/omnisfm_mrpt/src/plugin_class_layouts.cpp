// The stored layouts of the plugin's own classes (observation_tracked_features.cpp,
// observation_camera_model.cpp, observation_omni_image.cpp, catadioptric_camera_model.cpp).
#include "class_layouts.h"
#include "omnisfm/camera/camera_kinds.h"
#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

namespace omnisfm::mrpt_plugin {
namespace {

constexpr std::size_t kTimestamp = 8, kInt32 = 4, kDouble = 8;

void inner_camera(BoundedObjectCopy& in) {
  const std::string name = in.text();
  in.array(kDouble);  // its parameters
  camera::InnerKind kind;
  if (!camera::inner_kind_named(name, &kind)) in.layout_unknown();  // the model refuses it here
  if (kind == camera::InnerKind::kMrcal) {
    in.string();  // the lens model
    in.skip(2 * kInt32);
  }
}

void mirror(BoundedObjectCopy& in) {
  const std::string name = in.text();
  in.array(kDouble);     // its shape
  in.skip(2 * kDouble);  // its valid range
  camera::MirrorKind kind;
  if (!camera::mirror_kind_named(name, &kind)) in.layout_unknown();  // the model refuses it here
  if (kind == camera::MirrorKind::kTable) {
    in.array(kDouble);  // rho
    in.array(kDouble);  // z
  }
}

void camera_model(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  if (!in.flag()) return;  // no camera
  in.skip(2 * kInt32);     // the image's size
  inner_camera(in);
  mirror(in);
  in.skip(5 * kDouble);  // the mirror's pose
}

void tracked_features(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  in.skip(kTimestamp);
  in.string();  // the sensor label
  in.skip(kInt32);  // the frame
  in.object<mrpt::poses::CPose3D>();  // the sensor pose
  in.object<CCatadioptricCameraModel>();  // the camera model
  const auto features = in.value<std::uint32_t>();
  for (std::uint32_t i = 0; i < features; ++i) in.skip(kInt32 + 2 * kDouble);
}

void observation_camera_model(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  in.skip(kTimestamp);
  in.string();  // the sensor label
  in.object<mrpt::poses::CPose3D>();  // the sensor pose
  in.object<CCatadioptricCameraModel>();  // the model
}

void omni_image(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  observation_image_layout(in, in.value<std::uint8_t>());
  in.object<CCatadioptricCameraModel>();  // the model
}

}  // namespace

std::vector<ClassLayoutEntry> plugin_class_layouts() {
  return {{CLASS_ID(CCatadioptricCameraModel), camera_model},
          {CLASS_ID(CObservationTrackedFeatures), tracked_features},
          {CLASS_ID(CObservationCameraModel), observation_camera_model},
          {CLASS_ID(CObservationOmniImage), omni_image}};
}

}  // namespace omnisfm::mrpt_plugin
