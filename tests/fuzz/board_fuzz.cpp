// A board's corner positions, board.vnl (io::read_board): finite points.
#include "fuzz_contract.h"
#include "omnisfm/io/checkerboard_files.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "board.vnl");
  fuzz::expect_contract([&] {
    for (const auto& point : io::read_board(path))
      fuzz::require(point.allFinite(), "a board point that is not finite");
  });
  return 0;
}
