#include "omnisfm/io/atomic_write.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace omnisfm::io {

namespace fs = std::filesystem;

namespace {

bool process_runs(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
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
    if (process_runs(std::stol(pid))) continue;
    std::error_code ignored;
    fs::remove_all(entry.path(), ignored);
  }
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write) {
  const fs::path target(path);
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

}  // namespace omnisfm::io
