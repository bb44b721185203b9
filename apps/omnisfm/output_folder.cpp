#include "output_folder.h"

#include <fcntl.h>
#include <stdio.h>
#include <unistd.h>

#include <filesystem>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"

namespace omnisfm::app {
namespace fs = std::filesystem;

void write_folder(const std::string& dir, const std::function<void(const std::string&)>& write) {
  const fs::path target = fs::absolute(dir).lexically_normal();
  const fs::path parent = target.parent_path();
  if (!fs::is_directory(parent) || ::access(parent.c_str(), W_OK) != 0)
    throw io::InputError(dir, 0,
                         "cannot write here: " + parent.string() + " is not a writable folder");
  std::error_code ec;
  if (fs::exists(target, ec) && !fs::is_directory(target, ec))
    throw io::InputError(dir, 0, "exists and is not a folder");
  const std::string hidden = "." + target.filename().string();
  io::remove_abandoned_temporaries(parent, hidden + ".partial-", "");
  io::remove_abandoned_temporaries(parent, hidden + ".previous-", "");
  const std::string pid = std::to_string(::getpid());
  const fs::path partial = parent / (hidden + ".partial-" + pid);
  fs::remove_all(partial, ec);
  fs::create_directory(partial);
  try {
    write(partial.string());
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
  if (!fs::exists(target)) {
    fs::rename(partial, target);
    return;
  }
  // One atomic swap, so that the target is at every moment the earlier folder or the new one;
  // the earlier one, now under the partial name, goes after.
  if (::renameat2(AT_FDCWD, partial.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove_all(partial, ec);
    return;
  }
  // A file system without the swap: two renames, with the earlier folder kept aside between them.
  const fs::path previous = parent / (hidden + ".previous-" + pid);
  fs::rename(target, previous);
  fs::rename(partial, target);
  fs::remove_all(previous, ec);
}

}  // namespace omnisfm::app
