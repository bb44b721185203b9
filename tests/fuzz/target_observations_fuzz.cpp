// Target observations, observations.vnl (io::read_target_observations): finite pixels, lines
// that exist.
#include "fuzz_contract.h"
#include "omnisfm/io/target_files.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "observations.vnl");
  fuzz::expect_contract([&] {
    for (const auto& row : io::read_target_observations(path))
      fuzz::require(row.pixel.allFinite() && row.line > 0,
                    "a pixel not finite or a row at no line");
  });
  return 0;
}
