#include "verb_inputs.h"

#include <iostream>
#include <stdexcept>

#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/shared_data.h"

namespace omnisfm::app {

camera::CatadioptricCamera load_camera(const std::string& path) {
  return io::read_camera_file(path.empty() ? io::default_camera_file() : path);
}

io::VnlogTable read_table_or_stdin(const std::string& path) {
  if (path.empty() || path == "-") return io::VnlogTable::read(std::cin, "<stdin>");
  return io::VnlogTable::read(path);
}

void finish_stdout() {
  std::cout.flush();
  if (!std::cout) throw std::runtime_error("cannot write to standard output");
}

}  // namespace omnisfm::app
