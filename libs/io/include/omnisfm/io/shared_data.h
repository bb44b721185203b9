#pragma once
// omnisfm's shared data (example cameras, configs, small datasets): share/omnisfm beside the
// running program's bin folder (an installed program, even in a prefix moved elsewhere), else in
// the source tree this library was built from, else under the install prefix.

#include <string>
#include <vector>

namespace omnisfm::io {

// The folders searched, in order.
std::vector<std::string> shared_data_folders();

// The path of `relative` (e.g. "cameras/equiangular.ini") in the first folder that has it.
// Throws std::runtime_error naming the folders searched when none has it.
std::string find_shared_file(const std::string& relative);

// The camera used when a command is given none.
std::string default_camera_file();

}  // namespace omnisfm::io
