#include "omnisfm/io/atomic_write.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "omnisfm/io/input_error.h"

namespace omnisfm::io {

namespace fs = std::filesystem;

namespace {

// When the task `pid` (a process or a thread: kill() takes either) started, in seconds since the
// epoch, from /proc; NaN when there is no such task.
double task_start_time(long pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return NAN;
  // Field 22, starttime in clock ticks since boot, counted after the command's closing ')'.
  std::istringstream fields(line.substr(line.rfind(')') + 2));
  std::string field;
  for (int i = 3; i < 22 && fields >> field; ++i) {
  }
  double ticks = 0;
  if (!(fields >> ticks)) return NAN;
  std::ifstream system_stat("/proc/stat");
  for (std::string key; system_stat >> key;)
    if (key == "btime") {
      double boot = 0;
      system_stat >> boot;
      return boot + ticks / static_cast<double>(::sysconf(_SC_CLK_TCK));
    }
  return NAN;
}

// Whether the writer that named `entry` after its PID still runs. Process and thread ids are
// reused (32,768 of them, and busy machines cycle through them in minutes): a task holding the
// id now that started after the entry was last written is another one, and its writer is gone.
bool writer_runs(long pid, const fs::path& entry) {
  if (pid <= 0 || (::kill(static_cast<pid_t>(pid), 0) != 0 && errno != EPERM)) return false;
  struct ::stat status {};
  const double started = task_start_time(pid);
  if (std::isnan(started) || ::stat(entry.c_str(), &status) != 0) return true;
  const double written = static_cast<double>(status.st_mtim.tv_sec) + 1e-9 * status.st_mtim.tv_nsec;
  return started <= written + 1.0;  // /proc's boot time is in whole seconds
}

}  // namespace

void remove_abandoned_temporaries(const fs::path& folder, const std::string& prefix,
                                  const std::string& suffix) {
  std::error_code error;
  fs::directory_iterator entries(folder.empty() ? fs::path(".") : folder, error);
  if (error) return;
  for (const auto& entry : entries) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= prefix.size() + suffix.size() ||
        name.compare(0, prefix.size(), prefix) != 0 ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string pid = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    if (pid.find_first_not_of("0123456789") != std::string::npos || pid.size() > 9) continue;
    if (writer_runs(std::stol(pid), entry.path())) continue;
    std::error_code ignored;
    fs::remove_all(entry.path(), ignored);
  }
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write) {
  const fs::path target(path);
  // The rename would put a regular file in place of a device, a pipe or a link (as root, of
  // /dev/null itself).
  std::error_code status_error;
  const fs::file_status status = fs::symlink_status(target, status_error);
  if (fs::exists(status) && !fs::is_regular_file(status))
    throw InputError(path, 0,
                     "is not a regular file (a folder, device, pipe or link): give a "
                     "file's name");
  // The process id keeps concurrent writers of the same file apart, and tells a killed one's.
  const std::string prefix = target.stem().string() + ".tmp-";
  remove_abandoned_temporaries(target.parent_path(), prefix, target.extension().string());
  const fs::path temporary =
      target.parent_path() / (prefix + std::to_string(::getpid()) + target.extension().string());
  try {
    write(temporary.string());
    std::error_code error;
    fs::rename(temporary, target, error);
    if (error) throw std::runtime_error(path + ": cannot write the file: " + error.message());
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
}

void write_text_atomically(const std::string& path,
                           const std::function<void(std::ostream& out)>& write) {
  write_atomically(path, [&](const std::string& temporary_path) {
    std::ofstream out(temporary_path);
    if (!out) throw std::runtime_error(path + ": cannot create the file");
    write(out);
    out.close();
    if (!out) throw std::runtime_error(path + ": error while writing the file");
  });
}

fs::path folder_path(const std::string& given) {
  fs::path path = fs::absolute(given).lexically_normal();
  // lexically_normal keeps a trailing separator ("/a/b/" and "/a/." both end so).
  while (path.has_relative_path() && path.filename().empty()) path = path.parent_path();
  return path;
}

bool lies_within(const fs::path& path, const fs::path& folder) {
  std::error_code ignored;
  const fs::path inner = fs::weakly_canonical(fs::absolute(path), ignored);
  const fs::path outer = fs::weakly_canonical(fs::absolute(folder), ignored);
  return std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end()).first == outer.end();
}

void require_writable_folder(const std::string& path, const fs::path& folder) {
  std::error_code ec;
  const bool exists = fs::exists(folder, ec);
  if (ec)  // a folder above it that cannot be searched, say
    throw InputError(path, 0, "cannot write here: " + folder.string() + ": " + ec.message());
  if (!exists)
    throw InputError(path, 0,
                     "cannot write here: the folder " + folder.string() + " does not exist");
  if (!fs::is_directory(folder, ec))
    throw InputError(path, 0, "cannot write here: " + folder.string() + " is not a folder");
  if (::access(folder.c_str(), W_OK) != 0)
    throw InputError(path, 0,
                     "cannot write here: the folder " + folder.string() + " is not writable");
}

void check_folder_replaceable(const std::string& dir, const std::vector<std::string>& inputs) {
  if (dir.empty()) throw InputError("--out", 0, "is empty; give a folder");
  const fs::path target = folder_path(dir);
  // The temporary folder beside it adds to the name (".NAME.partial-PID"), which the file system
  // limits to 255 bytes.
  constexpr std::size_t kMaxName = 200;
  if (target.filename().string().size() > kMaxName)
    throw InputError(dir, 0,
                     "its name is " + std::to_string(target.filename().string().size()) +
                         " bytes long; at most " + std::to_string(kMaxName));
  if (!target.has_relative_path()) throw InputError(dir, 0, "is the root folder");
  require_writable_folder(dir, target.parent_path());
  std::error_code ec;
  // A link would be replaced by a folder of its own, its target left as it was.
  if (fs::is_symlink(fs::symlink_status(target, ec)))
    throw InputError(dir, 0, "is a symbolic link: give the folder it names");
  if (fs::exists(target, ec) && !fs::is_directory(target, ec))
    throw InputError(dir, 0, "exists and is not a folder");
  // Swapped away, the working folder would be deleted from under the shell that is in it.
  if (lies_within(fs::current_path(ec), target))
    throw InputError(dir, 0, "is the working folder, or holds it: give a folder inside it");
  for (const std::string& input : inputs)
    if (!input.empty() && lies_within(input, target))
      throw InputError(dir, 0,
                       "holds the input " + input +
                           ", which writing the folder anew would delete: give another folder");
  if (!fs::is_directory(target, ec)) return;
  if (fs::exists(target / kWrittenFolderMarker, ec)) return;
  fs::directory_iterator entries(target, ec);
  if (ec) throw InputError(dir, 0, "cannot read the folder: " + ec.message());
  if (entries != fs::directory_iterator())
    throw InputError(dir, 0,
                     "holds what omnisfm did not write (" + entries->path().filename().string() +
                         " among it), which writing the folder anew would delete: give a new or "
                         "empty folder, or one omnisfm wrote");
}

void write_folder_atomically(const std::string& dir,
                             const std::function<void(const std::string& folder)>& write) {
  check_folder_replaceable(dir);
  const fs::path target = folder_path(dir);
  const fs::path parent = target.parent_path();
  std::error_code ec;
  const std::string hidden = "." + target.filename().string();
  remove_abandoned_temporaries(parent, hidden + ".partial-", "");
  remove_abandoned_temporaries(parent, hidden + ".previous-", "");
  const std::string pid = std::to_string(::getpid());
  const fs::path partial = parent / (hidden + ".partial-" + pid);
  fs::remove_all(partial, ec);
  fs::create_directory(partial);
  try {
    write(partial.string());
    std::ofstream marker(partial / kWrittenFolderMarker);
    marker << "written by omnisfm: a later run may replace this folder whole\n";
    marker.close();
    if (!marker) throw std::runtime_error(dir + ": cannot write " + kWrittenFolderMarker);
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
  const int swap_error = errno;
  const auto fail = [&](const std::string& why) {
    fs::remove_all(partial, ec);
    throw std::runtime_error(dir + ": cannot move the new folder into place: " + why);
  };
  if (swap_error != EINVAL && swap_error != ENOSYS && swap_error != ENOTSUP)
    fail(std::generic_category().message(swap_error));
  // A file system without the swap: two renames, with the earlier folder kept aside between them
  // and put back if the second fails.
  const fs::path previous = parent / (hidden + ".previous-" + pid);
  fs::rename(target, previous, ec);
  if (ec) fail(ec.message());
  fs::rename(partial, target, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::rename(previous, target, ec);
    fail(why);
  }
  fs::remove_all(previous, ec);
}

}  // namespace omnisfm::io
