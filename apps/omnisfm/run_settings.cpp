#include "run_settings.h"

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/sfm/settings_file.h"

namespace omnisfm::app {

RunSettings read_run_settings(const std::string& path) {
  RunSettings settings;
  if (path.empty()) return settings;
  const io::IniFile ini = io::IniFile::read(path);
  for (const io::IniSection& section : ini.sections()) {
    if (section.name() == "run") {
      mrpt_plugin::read_run_options(section, &settings);
    } else if (section.name() == "sfm") {
      settings.sfm = sfm::read_sfm_settings(section);
    } else if (!(section.name().empty() && section.entries().empty())) {
      if (section.name().empty())
        section.fail(section.entries().front().key, "belongs in the [run] or [sfm] section");
      throw io::InputError(path, section.line(),
                           "unknown section [" + section.name() + "]: expected [run] or [sfm]");
    }
  }
  return settings;
}

}  // namespace omnisfm::app
