#pragma once
// Inputs that several verbs take the same way.

#include <string>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::app {

// The camera file `path`, or the default camera when `path` is empty.
camera::CatadioptricCamera load_camera(const std::string& path);

// The vnlog table in `path`, or standard input when `path` is empty or "-".
io::VnlogTable read_table_or_stdin(const std::string& path);

// Flushes standard output; throws std::runtime_error when anything written was lost.
void finish_stdout();

}  // namespace omnisfm::app
