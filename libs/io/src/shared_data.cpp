#include "omnisfm/io/shared_data.h"

#include <filesystem>
#include <stdexcept>

namespace omnisfm::io {

std::vector<std::string> shared_data_folders() {
  return {OMNISFM_SOURCE_SHARE_DIR, OMNISFM_INSTALL_SHARE_DIR};
}

std::string find_shared_file(const std::string& relative) {
  std::string searched;
  for (const std::string& folder : shared_data_folders()) {
    const std::filesystem::path candidate = std::filesystem::path(folder) / relative;
    std::error_code error;
    if (std::filesystem::is_regular_file(candidate, error)) return candidate.string();
    searched += (searched.empty() ? "" : ", ") + folder;
  }
  throw std::runtime_error("cannot find " + relative + " in " + searched);
}

std::string default_camera_file() { return find_shared_file("cameras/equiangular.ini"); }

}  // namespace omnisfm::io
