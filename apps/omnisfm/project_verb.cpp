#include <iostream>
#include <memory>
#include <string>

#include "omnisfm/io/projection_table.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {

void add_project_verb(CLI::App& app) {
  struct Options {
    std::string camera, points;
  };
  auto options = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "project", "Project `# x y z` points (frame C) to `# u v` pixels ('- -' where invalid)");
  verb->add_option("--camera", options->camera, "Camera file (default: the shipped equiangular)");
  verb->add_option("FILE", options->points, "vnlog table with x y z columns (default: stdin)");
  verb->callback([options] {
    const camera::CatadioptricCamera camera = load_camera(options->camera);
    const io::VnlogTable points = read_table_or_stdin(options->points);
    io::write_projected_points(camera, points, std::cout);
    finish_stdout();
  });
}

}  // namespace omnisfm::app
