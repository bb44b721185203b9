#include "output_folder.h"

#include <unistd.h>

#include <filesystem>

#include "omnisfm/io/input_error.h"

namespace omnisfm::app {
namespace fs = std::filesystem;

void write_folder(const std::string& dir, const std::function<void(const std::string&)>& write) {
  const fs::path target = fs::absolute(dir).lexically_normal();
  const fs::path parent = target.parent_path();
  if (!fs::is_directory(parent) || ::access(parent.c_str(), W_OK) != 0)
    throw io::InputError(dir, 0, "cannot write here: " + parent.string() + " is not a writable folder");
  std::error_code ec;
  if (fs::exists(target, ec) && !fs::is_directory(target, ec))
    throw io::InputError(dir, 0, "exists and is not a folder");
  const std::string suffix = std::to_string(::getpid());
  const fs::path partial = parent / ("." + target.filename().string() + ".partial-" + suffix);
  const fs::path previous = parent / ("." + target.filename().string() + ".previous-" + suffix);
  fs::remove_all(partial, ec);
  fs::create_directory(partial);
  try {
    write(partial.string());
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
  const bool replacing = fs::exists(target);
  if (replacing) fs::rename(target, previous);
  fs::rename(partial, target);
  if (replacing) fs::remove_all(previous, ec);
}

}  // namespace omnisfm::app
