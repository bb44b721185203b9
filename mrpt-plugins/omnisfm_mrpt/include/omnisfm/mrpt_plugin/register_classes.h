#pragma once
// The plugin's classes are registered with MRPT's class registry when the library loads. As with
// MRPT's own modules (mrpt::obs::registerAllClasses_mrpt_obs), a program may also call this, for
// instance after linking the library statically; registering again does no harm.

namespace omnisfm::mrpt_plugin {

void registerAllClasses_omnisfm_mrpt();

}  // namespace omnisfm::mrpt_plugin
