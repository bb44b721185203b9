#include <iostream>
#include <memory>
#include <string>

#include "omnisfm/io/projection_table.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {

void add_unproject_verb(CLI::App& app) {
  struct Options {
    std::string camera, pixels;
  };
  auto options = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "unproject",
      "Unproject `# u v` pixels to rays `# ox oy oz dx dy dz` in frame C (origin on the mirror, "
      "unit direction; '-' where invalid)");
  verb->add_option("--camera", options->camera, "Camera file (default: the shipped equiangular)");
  verb->add_option("FILE", options->pixels, "vnlog table with u v columns (default: stdin)");
  verb->callback([options] {
    const camera::CatadioptricCamera camera = load_camera(options->camera);
    const io::VnlogTable pixels = read_table_or_stdin(options->pixels);
    io::write_unprojected_pixels(camera, pixels, std::cout);
    finish_stdout();
  });
}

}  // namespace omnisfm::app
