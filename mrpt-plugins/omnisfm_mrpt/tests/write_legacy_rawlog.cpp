// write_legacy_rawlog PATH: writes the reference rawlog of the classes' current versions
// (legacy_rawlog_objects.h), for a class's next version to commit as data/versionN.rawlog.

#include <cstdio>
#include <exception>

#include "legacy_rawlog_objects.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_legacy_rawlog PATH\n");
    return 2;
  }
  try {
    omnisfm::mrpt_plugin::testing::write_reference_rawlog(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_legacy_rawlog: %s\n",
                 omnisfm::mrpt_plugin::mrpt_error_reason(e.what()).c_str());
    return 1;
  }
  std::printf("wrote %s\n", argv[1]);
  return 0;
}
