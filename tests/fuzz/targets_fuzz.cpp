// Surveyed targets, targets.vnl (io::read_targets): ids >= 0, finite positions.
#include "fuzz_contract.h"
#include "omnisfm/io/target_files.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "targets.vnl");
  fuzz::expect_contract([&] {
    for (const auto& [id, position] : io::read_targets(path))
      fuzz::require(id >= 0 && position.allFinite(), "a negative id or a position not finite");
  });
  return 0;
}
