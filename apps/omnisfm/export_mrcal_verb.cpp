#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisfm/calib/central_mrcal_model.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/io/shared_data.h"
#include "omnisfm/io/vnlog.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

// Grid columns across the image's longer side when no step is given: some thousands of valid
// pixels, many per control point.
constexpr double kDefaultGridColumns = 128;

void require_writable_file(const std::string& path) {
  if (std::filesystem::is_directory(path))
    throw io::InputError(path, 0, "cannot write here: it is a folder");
  require_writable_folder_of(path);
}

// Reported numbers are measurements, not values to read back exactly: a few digits.
std::string rounded(double value, int digits = 3) {
  char text[32];
  std::snprintf(text, sizeof text, "%.*g", digits, value);
  return text;
}

std::string error_summary(const calib::ReprojectionError& error) {
  return "RMS " + rounded(error.rms_px) + " px, worst " + rounded(error.worst_px) + " px " +
         (std::isinf(error.distance_m) ? std::string("at infinity")
                                       : "at " + rounded(error.distance_m, 6) + " m");
}

}  // namespace

void add_export_mrcal_verb(CLI::App& app) {
  struct Options {
    std::string camera, out;
    double distance_m = 0;
    int knots = 16;
    double grid_step_px = 0;
  };
  auto options = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "export-mrcal",
      "Fit the best central mrcal model (LENSMODEL_SPLINED_STEREOGRAPHIC) to the camera's "
      "reflected rays at a distance, write it as a .cameramodel, and print its reprojection "
      "error `# distance_m points failed rms_px worst_px` at that distance, ten times it and "
      "infinity");
  verb->add_option("--camera", options->camera, "Camera file (default: the shipped equiangular)");
  verb->add_option("--distance", options->distance_m,
                   "Distance of the fitted points from the mirror along each ray, metres "
                   "(1e-6 to 1e9)")
      ->required()
      ->check(number_between(1e-6, 1e9));
  verb->add_option("--out", options->out, "The .cameramodel to write (replaced whole)")->required();
  verb->add_option("--knots", options->knots, "Spline control points per axis")
      ->capture_default_str()
      ->check(whole_number_between(4, 100));
  verb->add_option("--grid-step", options->grid_step_px,
                   "Spacing of the fitted pixels, 2 px or more (default: the image's longer side "
                   "/ 128; at 0.5 px the fit took a minute and 4.8 GB)")
      ->check(number_between(2, 1e4));
  verb->callback([options] {
    const std::string camera_file =
        options->camera.empty() ? io::default_camera_file() : options->camera;
    const camera::CatadioptricCamera camera = load_camera(camera_file);
    require_writable_file(options->out);
    require_not_an_input(options->out, {options->camera});

    const double step_px =
        options->grid_step_px > 0
            ? options->grid_step_px
            : std::max(camera.image_width(), camera.image_height()) / kDefaultGridColumns;
    const std::vector<calib::PixelRay> rays = calib::valid_pixel_rays(camera, step_px);
    calib::CentralFitSettings settings;
    settings.distance_m = options->distance_m;
    settings.knots = options->knots;
    const calib::CentralMrcalModel model = [&] {
      try {
        return calib::fit_central_mrcal_model(camera, rays, settings);
      } catch (const std::invalid_argument& e) {
        throw io::InputError(camera_file, 0, e.what());
      }
    }();

    std::vector<calib::ReprojectionError> errors;
    for (double distance :
         {options->distance_m, 10 * options->distance_m, std::numeric_limits<double>::infinity()})
      errors.push_back(calib::reprojection_error(model, rays, distance));

    const std::vector<std::string> notes = {
        "omnisfm export-mrcal: the central mrcal model nearest to the camera " + camera_file + ",",
        "fitted to " + std::to_string(rays.size()) + " pixels on a " + io::format_double(step_px) +
            " px grid at " + io::format_double(options->distance_m) +
            " m from the mirror along their rays.",
        "Reprojection error: " + error_summary(errors[0]) + "; " + error_summary(errors[1]) + "; " +
            error_summary(errors[2]) + ".",
        "The extrinsics map the camera file's frame C (the reference) to this model's frame:",
        "the mirror frame turned half a turn about its x axis (z along the mirror's -z), its",
        "origin at the point nearest to all the rays. The mirror flips the image: fy < 0."};
    io::write_cameramodel(options->out, model, notes);

    io::VnlogWriter table(std::cout, {"distance_m", "points", "failed", "rms_px", "worst_px"});
    for (const calib::ReprojectionError& error : errors)
      table.row_texts({rounded(error.distance_m, 6), std::to_string(error.num_points),
                       std::to_string(error.num_failed), rounded(error.rms_px),
                       rounded(error.worst_px)});
    finish_stdout();
    std::cerr << "omnisfm: wrote " << options->out << ": " << model.lensmodel << ", "
              << error_summary(errors[0]) << "\n";
  });
}

}  // namespace omnisfm::app
