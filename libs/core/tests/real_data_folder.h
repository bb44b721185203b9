#pragma once
// Where the real catadioptric images are (../shared/data/real-catadioptric, mrcal's corners.vnl
// beside each set): $OMNISFM_REAL_DATA if set, else beside the source tree `source_dir`; empty
// with neither.

#include <cstdlib>
#include <filesystem>
#include <string>

namespace omnisfm::test {

inline std::string real_data_folder(const char* source_dir) {
  if (const char* given = std::getenv("OMNISFM_REAL_DATA")) return given;
  if (!source_dir) return "";
  return (std::filesystem::path(source_dir) / ".." / "shared" / "data" / "real-catadioptric")
      .lexically_normal()
      .string();
}

}  // namespace omnisfm::test
