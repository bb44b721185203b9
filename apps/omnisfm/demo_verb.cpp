// A first look at the camera model until the end-to-end demo exists: the points of a room's
// walls, floor and ceiling seen through the default camera.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/vnlog.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

// A 6 x 4 x 3 m room with the camera in its middle, 1.2 m above the floor, looking up at the
// mirror. Frame C: z up toward the mirror, x and y horizontal.
std::vector<Eigen::Vector3d> room_points() {
  constexpr double half_x = 3.0, half_y = 2.0, floor_z = -1.2, ceiling_z = 1.8, step = 0.2;
  const auto samples = [](double from, double to) {
    std::vector<double> values;
    const int count = static_cast<int>((to - from) / step + 0.5);
    for (int i = 0; i <= count; ++i) values.push_back(from + (to - from) * i / count);
    return values;
  };
  std::vector<Eigen::Vector3d> points;
  for (double x : samples(-half_x, half_x)) {
    for (double y : samples(-half_y, half_y)) {
      points.emplace_back(x, y, floor_z);
      points.emplace_back(x, y, ceiling_z);
    }
  }
  for (double z : samples(floor_z + step, ceiling_z - step)) {
    for (double x : samples(-half_x, half_x)) {
      points.emplace_back(x, -half_y, z);
      points.emplace_back(x, half_y, z);
    }
    for (double y : samples(-half_y + step, half_y - step)) {
      points.emplace_back(-half_x, y, z);
      points.emplace_back(half_x, y, z);
    }
  }
  return points;
}

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string gnuplot_quoted(const std::string& text) {
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') quoted += '\\';
    quoted += c;
  }
  return quoted + "\"";
}

// Plots the pixels in the image frame (v down), coloured by height; false when gnuplot failed.
bool plot(const std::filesystem::path& table, const std::filesystem::path& image, int width,
          int height) {
  const std::filesystem::path script = image.parent_path() / "projected.gp";
  {
    std::ofstream out(script);
    out << "set terminal pngcairo size " << width << "," << height << "\n"
        << "set output " << gnuplot_quoted(image.string()) << "\n"
        << "set datafile missing '-'\n"
        << "set xrange [-0.5:" << width - 0.5 << "]\n"
        << "set yrange [" << height - 0.5 << ":-0.5]\n"
        << "set size ratio -1\n"
        << "set xlabel 'u (px)'\nset ylabel 'v (px)'\nset cblabel 'z (m)'\n"
        << "set title 'Room points through the default camera'\n"
        << "plot " << gnuplot_quoted(table.string())
        << " using 4:5:3 with points pt 7 ps 0.4 palette notitle\n";
    if (!out) return false;
  }
  const std::string command = "gnuplot " + shell_quoted(script.string()) + " 2>/dev/null";
  return std::system(command.c_str()) == 0;
}

bool have_gnuplot() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

void run_demo(const std::string& camera_path, const std::string& out_dir) {
  const camera::CatadioptricCamera camera = load_camera(camera_path);
  std::filesystem::create_directories(out_dir);
  const std::filesystem::path table = std::filesystem::path(out_dir) / "projected.vnl";

  const std::vector<Eigen::Vector3d> points = room_points();
  int visible = 0;
  io::write_text_atomically(table.string(), [&](std::ostream& out) {
    io::VnlogWriter writer(out, {"x", "y", "z", "u", "v"});
    writer.comment("Points of a 6 x 4 x 3 m room in frame C and their pixels ('-': not seen)");
    const double missing = std::numeric_limits<double>::quiet_NaN();
    for (const Eigen::Vector3d& X : points) {
      Eigen::Vector2d pixel;
      if (camera.project(X, &pixel) && camera.in_image(pixel)) {
        ++visible;
        writer.row({X.x(), X.y(), X.z(), pixel.x(), pixel.y()});
      } else {
        writer.row({X.x(), X.y(), X.z(), missing, missing});
      }
    }
  });

  std::string wrote = table.string();
  if (have_gnuplot()) {
    const std::filesystem::path image = std::filesystem::path(out_dir) / "projected.png";
    if (plot(table, image, camera.image_width(), camera.image_height())) {
      wrote += " and " + image.string();
    } else {
      std::cerr << "omnisfm: gnuplot failed; no plot written\n";
    }
  }
  std::cout << "demo: " << visible << " of " << points.size()
            << " room points seen in the image; wrote " << wrote << "\n";
}

}  // namespace

void add_demo_verb(CLI::App& app) {
  struct Options {
    std::string camera, out = "out";
  };
  auto options = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "demo", "Project a synthetic room through the default camera into DIR/projected.vnl "
              "(and DIR/projected.png when gnuplot is installed)");
  verb->add_option("--out", options->out, "Output folder")->capture_default_str();
  verb->add_option("--camera", options->camera, "Camera file (default: the shipped equiangular)");
  verb->callback([options] { run_demo(options->camera, options->out); });
}

}  // namespace omnisfm::app
