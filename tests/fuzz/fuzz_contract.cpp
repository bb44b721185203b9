#include "fuzz_contract.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace omnisfm::fuzz {

namespace fs = std::filesystem;

namespace {

struct ScratchFolder {
  ScratchFolder() {
    std::string pattern = (fs::temp_directory_path() / "omnisfm-fuzz-XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) {
      std::perror("omnisfm fuzz: mkdtemp");
      std::abort();
    }
    path = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  std::string path;
};

}  // namespace

const std::string& scratch_folder() {
  static const ScratchFolder folder;
  return folder.path;
}

std::string write_input(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::string path = scratch_folder() + "/" + name;
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!out) broken("cannot write the input to " + path);
  return path;
}

void broken(const std::string& what) {
  std::fprintf(stderr, "fuzz contract broken: %s\n", what.c_str());
  std::abort();
}

void check_input_error(const io::InputError& error) {
  const std::string what = error.what();
  if (error.file().empty()) broken("an InputError that names no file: " + what);
  if (io::printable_text(what) != what) broken("an InputError that is not printable text");
  if (error.line() < 0) broken("an InputError at a negative line: " + what);
  if (error.line() > 0) {
    // The line must exist in the file it names (when that file is there to count).
    std::ifstream in(error.file(), std::ios::binary);
    if (in) {
      const std::string text((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
      const long lines = std::count(text.begin(), text.end(), '\n') + 1;
      if (error.line() > lines) broken("an InputError past the file's last line: " + what);
    }
  }
}

}  // namespace omnisfm::fuzz
