// Registers the plugin's classes with MRPT's class registry when the library is loaded, whether it
// is linked or opened as a plugin (`rawlog-edit -p libomnisfm_mrpt.so`): reading a rawlog finds a
// class by its stored name in that registry.

#include <mrpt/core/initializer.h>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

MRPT_INITIALIZER(register_omnisfm_mrpt_classes) {
  using mrpt::rtti::registerClass;
  registerClass(CLASS_ID(omnisfm::mrpt_plugin::CCatadioptricCameraModel));
  registerClass(CLASS_ID(omnisfm::mrpt_plugin::CObservationOmniImage));
  registerClass(CLASS_ID(omnisfm::mrpt_plugin::CObservationTrackedFeatures));
}
