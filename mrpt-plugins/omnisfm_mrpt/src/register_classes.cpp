// Registers the plugin's classes with MRPT's class registry when the library is loaded, whether it
// is linked or opened as a plugin (`rawlog-edit -p libomnisfm_mrpt_classes.so`): reading a rawlog
// finds a class by its stored name in that registry.

#include "omnisfm/mrpt_plugin/register_classes.h"

#include <mrpt/core/initializer.h>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

namespace omnisfm::mrpt_plugin {

void registerAllClasses_omnisfm_mrpt() {
  using mrpt::rtti::registerClass;
  registerClass(CLASS_ID(CCatadioptricCameraModel));
  registerClass(CLASS_ID(CObservationCameraModel));
  registerClass(CLASS_ID(CObservationOmniImage));
  registerClass(CLASS_ID(CObservationTrackedFeatures));
}

}  // namespace omnisfm::mrpt_plugin

MRPT_INITIALIZER(register_omnisfm_mrpt_classes) {
  omnisfm::mrpt_plugin::registerAllClasses_omnisfm_mrpt();
}
