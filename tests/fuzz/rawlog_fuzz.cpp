// MRPT rawlogs through the plugin's classes: images (mrpt_plugin::for_each_rawlog_image) and
// tracked features (mrpt_plugin::read_rawlog_tracks). Damage ends the reading with a problem
// that names the file; what came before it keeps the reader's guarantees.
#include "fuzz_contract.h"
#include "omnisfm/mrpt_plugin/rawlog_input.h"

using namespace omnisfm;

namespace {

// `input` is the file's bytes: a problem may echo them (a damaged class name), and fuzzing finds
// the file's name to put there.
void require_named(const mrpt_plugin::RawlogReadResult& result, const std::string& path,
                   const std::string& input) {
  fuzz::require(result.used <= result.objects, "more objects used than read");
  if (!result.complete()) {
    fuzz::require(result.problem.find(path) == std::string::npos ||
                      input.find(path) != std::string::npos,
                  "a problem that repeats the file's name (the caller names it)");
    fuzz::require(io::printable_text(result.problem) == result.problem,
                  "a problem that is not printable text");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "input.rawlog");
  const std::string input(reinterpret_cast<const char*>(data), size);
  fuzz::expect_contract([&] {
    const auto result =
        mrpt_plugin::for_each_rawlog_image(path, [](mrpt_plugin::RawlogImage& image) {
          fuzz::require(image.grey.type() == CV_8UC1 && !image.grey.empty(),
                        "an image not 8-bit grey");
        });
    require_named(result, path, input);
  });
  fuzz::expect_contract([&] {
    mrpt_plugin::RawlogTracks tracks;
    const auto result = mrpt_plugin::read_rawlog_tracks(path, &tracks);
    require_named(result, path, input);
    for (const auto& observation : tracks.observations)
      fuzz::require(observation.pixel.allFinite(), "a tracked feature not finite");
  });
  return 0;
}
