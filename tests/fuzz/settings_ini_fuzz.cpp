// The settings INI files: `sfm --config` ([sfm]) and `run --config` ([sfm] and [run]).
#include "fuzz_contract.h"
#include "omnisfm/sfm/settings_file.h"
#include "run_settings.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "settings.ini");
  fuzz::expect_contract([&] { sfm::read_sfm_settings(path); });
  fuzz::expect_contract([&] { app::read_run_settings(path); });
  return 0;
}
