#include "omnisfm/io/shared_data.h"

#include <filesystem>
#include <stdexcept>

namespace omnisfm::io {

std::vector<std::string> shared_data_folders() {
  std::vector<std::string> folders;
  // An installed program's own prefix first, wherever the prefix was moved to.
  std::error_code error;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path beside =
        (program.parent_path() / OMNISFM_SHARE_DIR_FROM_BINDIR).lexically_normal();
    if (std::filesystem::is_directory(beside, error)) folders.push_back(beside.string());
  }
  folders.push_back(OMNISFM_SOURCE_SHARE_DIR);
  folders.push_back(OMNISFM_INSTALL_SHARE_DIR);
  return folders;
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
