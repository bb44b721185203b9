#include "omnisfm/io/atomic_write.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>

namespace omnisfm::io {

namespace fs = std::filesystem;

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& temporary_path)>& write) {
  const fs::path target(path);
  // The process id keeps concurrent writers of the same file apart.
  const fs::path temporary =
      target.parent_path() / (target.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                              target.extension().string());
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
