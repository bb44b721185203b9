// omnisfm calibrate: the mirror-to-camera transform from surveyed targets (the paper's method), or
// any chosen camera parameters from checkerboards; writes the calibrated camera with its
// covariance, and a report folder beside it.

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "board_images.h"
#include "omnisfm/calib/calibration_report.h"
#include "omnisfm/calib/calibration_views.h"
#include "omnisfm/calib/cross_validation.h"
#include "omnisfm/calib/projection_uncertainty.h"
#include "omnisfm/calib/staged_calibration.h"
#include "omnisfm/calib/starting_camera.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/io/checkerboard_files.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/io/target_files.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

struct CalibrateOptions {
  std::string camera, targets, observations, corners, board, out;
  // Without a starting camera file: the images to detect the boards in, or the corners' image
  // size, and the kind of mirror and lens to start from.
  std::string images, mirror, inner = "pinhole", image_size;
  bool estimate_given = false;
  double object_spacing = 0;
  int object_width_n = 0, object_height_n = 0;
  std::string estimate = "mirror-pose";
  int holdout = 0;
  int cross_validate = 0;
  double outlier_sigma = 4;
  double uncertainty_distance = 1;
};

std::vector<std::string> comma_separated(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) items.push_back(item);
  }
  return items;
}

// The views, and where they came from for the report and for errors.
struct Inputs {
  std::vector<calib::CalibrationView> views;
  std::vector<std::string> description;
  std::string observations_file;  // the file that errors about observations point at
};

// A pixel beyond the image is a slip of the file, not a measurement: one corner thousands of
// pixels out had the solve converge at an RMS of 34 px. Bounds as the tracks' (tracks_file.h).
void require_inside_image(const Eigen::Vector2d& pixel, const camera::CatadioptricCamera& camera,
                          const std::string& file, int line, const std::string& size_source) {
  if (camera.in_image(pixel)) return;
  std::ostringstream message;
  message << "pixel (" << pixel.x() << ", " << pixel.y() << ") lies outside the "
          << camera.image_width() << "x" << camera.image_height() << " image (" << size_source
          << ")";
  throw io::InputError(file, line, message.str());
}

// The mean distance, in one image where every corner was found, between the corners that a
// board `across` points wide, in rows, makes neighbours (along a row and down a column): the right
// width's are a square apart, a wrong one's include diagonals and jumps across the board. NaN
// where corners are missing.
double neighbour_distance(const io::ImageCorners& image, int across, int down) {
  if (static_cast<int>(image.pixels.size()) != across * down ||
      image.num_detected() != across * down)
    return NAN;
  double sum = 0;
  int pairs = 0;
  for (int k = 0; k < across * down; ++k) {
    if (k % across + 1 < across) sum += (image.pixels[k + 1] - image.pixels[k]).norm(), ++pairs;
    if (k + across < across * down)
      sum += (image.pixels[k + across] - image.pixels[k]).norm(), ++pairs;
  }
  return sum / pairs;
}

// A W x H board given as H x W has as many points, and calibrates to tens of pixels: refused,
// naming the size the corners' order shows. Per image the given width's mean neighbour distance
// over the swapped one's: on the shared sets' images a right board gives 0.39-0.58 and a swapped
// one 1.73-2.56, vmr's 6 x 7 given as 7 x 6 the least (its columns' neighbours become diagonals,
// each row's end a jump back across the board); the median over the images decides.
void check_board_orientation(const std::vector<io::ImageCorners>& images,
                             const CalibrateOptions& o) {
  constexpr double kSwappedRatio = 1.4;
  const int w = o.object_width_n, h = o.object_height_n;
  if (w == h) return;
  std::vector<double> ratios;
  for (const io::ImageCorners& image : images) {
    const double ratio = neighbour_distance(image, w, h) / neighbour_distance(image, h, w);
    if (std::isfinite(ratio)) ratios.push_back(ratio);
  }
  if (!ratios.empty() && core::percentile(ratios, 0.5) > kSwappedRatio)
    throw io::InputError(o.corners, 0,
                         "its corners run in rows of " + std::to_string(h) + ", not " +
                             std::to_string(w) + ": the board is " + std::to_string(h) + "x" +
                             std::to_string(w) +
                             " points; swap --object-width-n and "
                             "--object-height-n");
}

Inputs read_inputs(const CalibrateOptions& o, const std::string& camera_description,
                   const camera::CatadioptricCamera& camera) {
  const std::string size_source =
      o.camera.empty() ? "--image-size, or the images'" : "the size in " + o.camera;
  Inputs inputs;
  inputs.description.push_back("camera " + camera_description);
  if (!o.targets.empty()) {
    const auto targets = io::read_targets(o.targets);
    const auto rows = io::read_target_observations(o.observations);
    for (const auto& row : rows)
      require_inside_image(row.pixel, camera, o.observations, row.line, size_source);
    inputs.views = calib::target_views(targets, rows, o.observations);
    inputs.observations_file = o.observations;
    inputs.description.push_back("targets " + o.targets + " (" + std::to_string(targets.size()) +
                                 " surveyed)");
    inputs.description.push_back("observations " + o.observations + " (" +
                                 std::to_string(rows.size()) + " in " +
                                 std::to_string(inputs.views.size()) + " images)");
    return inputs;
  }
  std::vector<Eigen::Vector3d> board;
  std::string board_source;
  if (!o.board.empty()) {
    board = io::read_board(o.board);
    board_source = o.board;
  } else {
    try {
      board = io::regular_board(o.object_spacing, o.object_width_n, o.object_height_n);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("--object-spacing/--object-width-n/--object-height-n", e.what());
    }
    std::ostringstream source;
    source << o.object_width_n << "x" << o.object_height_n << " points, " << o.object_spacing
           << " m apart";
    board_source = source.str();
  }
  const auto images = io::read_corners(o.corners);
  if (o.board.empty()) check_board_orientation(images, o);
  for (const io::ImageCorners& corners : images)
    for (std::size_t k = 0; k < corners.pixels.size(); ++k)
      if (corners.detected[k])
        require_inside_image(corners.pixels[k], camera, o.corners, corners.lines[k], size_source);
  inputs.views = calib::board_views(images, board, o.corners, board_source);
  inputs.observations_file = o.corners;
  int observations = 0;
  for (const auto& view : inputs.views) observations += static_cast<int>(view.points.size());
  inputs.description.push_back("corners " + o.corners + " (" + std::to_string(observations) +
                               " detected in " + std::to_string(inputs.views.size()) + " of " +
                               std::to_string(images.size()) + " images)");
  inputs.description.push_back("board " + board_source);
  return inputs;
}

// Progress on one terminal line, only when stderr is a terminal.
std::function<void(const std::string&, int, double)> terminal_progress() {
  if (!::isatty(STDERR_FILENO)) return nullptr;
  return [](const std::string& stage, int iteration, double rms) {
    std::fprintf(stderr, "\romnisfm: calibrating, stage %-40s iteration %4d, RMS %9.4f px",
                 stage.c_str(), iteration, rms);
    std::fflush(stderr);
  };
}

// Where calibrate --images writes the corners it found: beside the camera file.
std::string detected_corners_file(const std::string& camera_file) {
  const fs::path out(camera_file);
  return (out.parent_path() / (out.stem().string() + ".corners.vnl")).string();
}

std::string report_folder_for(const std::string& camera_file) {
  fs::path path(camera_file);
  return (path.parent_path() / (path.stem().string() + ".report")).string();
}

// The report folder replaced whole, so that nothing of an earlier run's report stays beside this
// one's. Returns what gnuplot could not draw.
std::string write_report(const std::string& folder, const calib::CalibrationOutcome& outcome) {
  std::string note;
  io::write_folder_atomically(folder, [&](const std::string& dir) {
    note = calib::write_calibration_report(dir, outcome);
  });
  return note;
}

// --holdout's views taken out of `inputs` (and named in its description): they leave the
// calibration and come back to be measured against it.
std::vector<calib::CalibrationView> hold_out(const CalibrateOptions& o, Inputs* inputs) {
  if (o.holdout <= 0) return {};
  calib::ViewPartition partition;
  try {
    partition = calib::hold_out_views(inputs->views, o.holdout);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--holdout", e.what());
  }
  inputs->views = std::move(partition.kept);
  std::string names;
  for (const auto& view : partition.held) names += (names.empty() ? "" : ", ") + view.name;
  inputs->description.push_back("held out: " + names);
  return std::move(partition.held);
}

// --cross-validate's folds, each calibrated from `start` as the camera written; progress a line
// per fold.
calib::CrossValidation cross_validated(const CalibrateOptions& o,
                                       const camera::CatadioptricCamera& start,
                                       const std::vector<calib::CalibrationView>& views,
                                       const calib::StagedSettings& settings,
                                       const std::string& observations_file) {
  calib::StagedSettings fold_settings = settings;
  fold_settings.progress = nullptr;
  const bool show = static_cast<bool>(settings.progress);
  calib::CrossValidation cross_validation;
  try {
    cross_validation =
        calib::cross_validate(start, views, fold_settings, o.cross_validate, [&](int fold) {
          if (show)
            std::cerr << "\rcross-validation: fold " << fold + 1 << " of " << o.cross_validate
                      << std::flush;
        });
  } catch (const std::invalid_argument& e) {
    if (show) std::cerr << "\n";
    throw io::InputError(observations_file, 0, std::string("cross-validation: ") + e.what());
  }
  if (show) std::cerr << "\n";
  return cross_validation;
}

// The line on standard error that says what was written and how well it fits.
void print_written(const CalibrateOptions& o, const calib::CalibrationOutcome& outcome,
                   const std::string& folder, const std::string& note) {
  const calib::CalibrationReport& final = outcome.report->final;
  std::cerr << "omnisfm: wrote " << o.out << ": RMS " << final.rms_px
            << " px per coordinate, worst " << final.worst_px << " px, " << final.num_outliers
            << " outliers of " << final.num_observations << " observations";
  if (const calib::HeldOutResult* held_out = outcome.held_out) {
    std::cerr << "; held-out RMS " << held_out->rms_px << " px over "
              << held_out->num_observations << " observations";
  }
  if (const calib::CrossValidation* folds = outcome.cross_validation) {
    std::cerr << "; " << o.cross_validate << "-fold cross-validation: pooled held-out RMS "
              << folds->pooled_rms_px << " px over " << folds->num_observations
              << " observations";
    if (folds->folds_not_converged > 0)
      std::cerr << " (" << folds->folds_not_converged << " folds did not converge)";
  }
  std::cerr << "; report in " << folder << "\n";
  if (!note.empty()) std::cerr << "omnisfm: warning: " << note << "\n";
}

// --image-size's "WxH".
cv::Size parse_image_size(const std::string& text) {
  // Each side a whole number of pixels, 2 to 100,000 (sscanf's %d overflowed on 99999999999).
  constexpr int kMaxSide = 100000;
  const std::size_t x = text.find('x');
  int width = 0, height = 0;
  if (x == std::string::npos || !io::parse_int(text.substr(0, x), &width) ||
      !io::parse_int(text.substr(x + 1), &height) || width < 2 || height < 2 || width > kMaxSide ||
      height > kMaxSide)
    throw CLI::ValidationError("--image-size", "must be WIDTHxHEIGHT in pixels (2 to " +
                                                   std::to_string(kMaxSide) + " each), not '" +
                                                   text + "'");
  return {width, height};
}

// Where the mirror's picture lies when only corners are given: about the image's centre, out
// beyond the farthest corner and in short of the nearest.
calib::MirrorImage mirror_around_corners(const std::string& corners_file, cv::Size size) {
  calib::MirrorImage mirror;
  mirror.centre = Eigen::Vector2d((size.width - 1) / 2.0, (size.height - 1) / 2.0);
  double nearest = INFINITY, farthest = 0;
  for (const io::ImageCorners& image : io::read_corners(corners_file))
    for (std::size_t k = 0; k < image.pixels.size(); ++k)
      if (image.detected[k]) {
        const double r = (image.pixels[k] - mirror.centre).norm();
        nearest = std::min(nearest, r);
        farthest = std::max(farthest, r);
      }
  if (farthest == 0) throw io::InputError(corners_file, 0, "no observations to calibrate from");
  mirror.inner_radius = std::max(1.0, 0.8 * nearest);
  mirror.outer_radius = 1.15 * farthest;
  return mirror;
}

// A generic start's kind in words: "conic mirror before a pinhole lens".
std::string kind_words(const std::string& mirror, const std::string& inner) {
  return mirror + " mirror before a " + (inner == "orthographic" ? "telecentric" : "pinhole") +
         " lens";
}
std::string kind_phrase(const std::string& mirror, const std::string& inner) {
  return (mirror == "equiangular" ? "an " : "a ") + kind_words(mirror, inner);
}

// Where a generic start's picture lies: the mirror found in the images, or about the image's
// centre around the corners.
struct StartPicture {
  cv::Size size;
  calib::MirrorImage mirror;
  bool from_images = false;
};

StartPicture start_picture(const CalibrateOptions& o) {
  if (!o.images.empty()) return {image_size_of(o.images), mirror_of(o.images), true};
  const cv::Size size = parse_image_size(o.image_size);
  return {size, mirror_around_corners(o.corners, size), false};
}

// The generic camera of a --mirror and --inner kind about a picture.
camera::CatadioptricCamera generic_start(const std::string& mirror, const std::string& inner,
                                         const StartPicture& picture) {
  const calib::StartingMirror mirror_kind =
      mirror == "equiangular" ? calib::StartingMirror::kEquiangular : calib::StartingMirror::kConic;
  const calib::StartingInner inner_kind = inner == "orthographic"
                                              ? calib::StartingInner::kOrthographic
                                              : calib::StartingInner::kPinhole;
  try {
    return calib::starting_camera(picture.mirror, picture.size.width, picture.size.height,
                                  mirror_kind, inner_kind);
  } catch (const std::invalid_argument& e) {
    throw CLI::ValidationError("--mirror", e.what());
  }
}

// The starting camera and how the report names it: the --camera file, or a generic start of the
// --mirror and --inner kinds from the mirror's picture in the images (or around the corners).
struct Start {
  std::unique_ptr<camera::CatadioptricCamera> camera;
  std::string description;
  std::optional<StartPicture> picture;  // of a generic start
};

Start starting_camera(const CalibrateOptions& o) {
  Start start;
  if (!o.camera.empty()) {
    start.camera = std::make_unique<camera::CatadioptricCamera>(load_camera(o.camera));
    start.description = o.camera;
    return start;
  }
  const StartPicture picture = start_picture(o);
  start.camera =
      std::make_unique<camera::CatadioptricCamera>(generic_start(o.mirror, o.inner, picture));
  char text[200];
  std::snprintf(text, sizeof text, "from %s: centre (%.1f, %.1f), picture %.0f-%.0f px",
                picture.from_images ? "the images' mirror" : "the corners' spread",
                picture.mirror.centre.x(), picture.mirror.centre.y(), picture.mirror.inner_radius,
                picture.mirror.outer_radius);
  start.description = "a generic " + kind_words(o.mirror, o.inner) + ", " + text;
  start.picture = picture;
  return start;
}

// The RMS per coordinate over every observation a calibration could project, its outliers too:
// fits that rejected different observations compare by it (on the omnidir rig's 18 images a
// telecentric lens fits its inliers at 0.2438 px rejecting 28, a pinhole at 0.2558 rejecting 12;
// over every observation the pinhole fits better).
double rms_over_all(const calib::CalibrationReport& report) {
  double sum2 = 0;
  int count = 0;
  for (const calib::ObservationResidual& r : report.residuals)
    if (r.residual.allFinite()) {
      sum2 += r.residual.squaredNorm();
      ++count;
    }
  return count > 0 ? std::sqrt(sum2 / (2 * count)) : INFINITY;
}

// A start-free calibration that did not converge: the generic kinds not named, each calibrated
// from its own start about the same picture on the same views; of those that converge, the one
// with the least RMS over every observation, said as the options to give, or "" where none
// converges (a start that finds no pose for some view does not).
std::string other_kind_that_converges(const CalibrateOptions& o, const StartPicture& picture,
                                      const std::vector<calib::CalibrationView>& views,
                                      calib::StagedSettings settings) {
  settings.progress = nullptr;
  std::string converges;
  double best = INFINITY;
  for (const auto& [mirror, inner] : {std::pair<std::string, std::string>{"conic", "pinhole"},
                                      {"conic", "orthographic"},
                                      {"equiangular", "pinhole"}}) {
    if (mirror == o.mirror && inner == o.inner) continue;
    camera::CatadioptricCamera camera = generic_start(mirror, inner, picture);
    std::vector<calib::CalibrationView> solved = views;
    calib::StagedReport report;
    try {
      report = calib::calibrate_in_stages(&camera, &solved, settings);
    } catch (const std::exception&) {
      continue;
    }
    if (!report.final.converged || !(rms_over_all(report.final) < best)) continue;
    best = rms_over_all(report.final);
    char text[120];
    std::snprintf(text, sizeof text, " converges (RMS %.4g px per coordinate, %d outliers): give",
                  report.final.rms_px, report.final.num_outliers);
    converges = kind_phrase(mirror, inner) + text;
    if (mirror != o.mirror) converges += " --mirror " + mirror;
    if (inner != o.inner) converges += " --inner " + inner;
  }
  return converges;
}

// --images: the boards detected (through the start's generic views, or the --camera model) and
// written as OUT-stem.corners.vnl beside the camera file, which the calibration then reads.
std::string detect_corners_for(const CalibrateOptions& o, const Start& start) {
  const cv::Size grid(o.object_width_n, o.object_height_n);
  // OpenCV's detector finds no board narrower than 3 points (detect-corners' bound).
  if (grid.width < 3 || grid.height < 3)
    throw CLI::ValidationError("--object-width-n/--object-height-n",
                               "with --images must each be at least 3, not " +
                                   std::to_string(grid.width) + " and " +
                                   std::to_string(grid.height));
  std::unique_ptr<calib::BoardDetector> detector =
      start.picture ? std::make_unique<calib::BoardDetector>(start.picture->mirror, grid)
                    : std::make_unique<calib::BoardDetector>(*start.camera, grid);
  std::optional<cv::Size> camera_size;
  if (!start.picture)
    camera_size = cv::Size(start.camera->image_width(), start.camera->image_height());
  std::vector<cv::Size> seen;  // in the images without the grid's board
  const std::vector<io::ImageCorners> corners = detect_boards(
      o.images, detector.get(),
      [&](const BoardImage& image) {
        if (!image.board) seen.push_back(image.board_seen);
      },
      camera_size);
  int boards = 0;
  for (const io::ImageCorners& image : corners) boards += image.num_detected() > 0;
  // Fewer views than the staged solve's groups can be told apart from.
  constexpr int kMinBoards = 3;
  if (boards < kMinBoards) {
    // Where some image holds the grid, its size is right, and the others' is no advice.
    const std::string note = boards > 0 ? "" : boards_seen_note(seen, grid);
    throw io::InputError(o.images, 0,
                         "a whole " + std::to_string(grid.width) + "x" +
                             std::to_string(grid.height) + " board was found in " +
                             std::to_string(boards) + " of " + std::to_string(corners.size()) +
                             " images; calibrating needs at least " + std::to_string(kMinBoards) +
                             (note.empty() ? "" : "; " + note));
  }
  const std::string file = detected_corners_file(o.out);
  io::write_corners(file, corners);
  std::cerr << "omnisfm: found a " << grid.width << "x" << grid.height << " board in " << boards
            << " of " << corners.size() << " images; their corners are in " << file << "\n";
  return file;
}

void run_calibrate(CalibrateOptions o) {
  require_writable_folder_of(o.out);
  const fs::path name = fs::path(o.out).filename();
  if (fs::is_directory(o.out) || name.empty() || name == "." || name == "..")
    throw io::InputError(o.out, 0, "is a folder; give the camera file's name");
  io::check_folder_replaceable(report_folder_for(o.out),
                               {o.camera, o.targets, o.observations, o.corners, o.board, o.images});
  require_not_an_input(o.out, {o.camera, o.targets, o.observations, o.corners, o.board});
  if (!o.images.empty()) require_not_an_input(detected_corners_file(o.out), {o.camera, o.board});
  const Start start_camera = starting_camera(o);
  camera::CatadioptricCamera camera = *start_camera.camera;
  if (!o.images.empty()) o.corners = detect_corners_for(o, start_camera);
  // A generic start is far from the camera: its lens and mirror are freed too.
  if (o.camera.empty() && !o.estimate_given) o.estimate = "mirror-pose,intrinsics,mirror-shape";
  Inputs inputs = read_inputs(o, start_camera.description, camera);
  if (inputs.views.empty()) {
    throw io::InputError(inputs.observations_file, 0, "no observations to calibrate from");
  }
  const std::vector<calib::CalibrationView> held = hold_out(o, &inputs);

  const int num_views = static_cast<int>(inputs.views.size());
  if (o.cross_validate > num_views)
    throw CLI::ValidationError("--cross-validate", "cannot make " +
                                                       std::to_string(o.cross_validate) +
                                                       " folds of " + std::to_string(num_views) +
                                                       " views");
  const camera::CatadioptricCamera start = camera;
  const std::vector<calib::CalibrationView> all_views = inputs.views;
  calib::StagedSettings settings;
  settings.groups = comma_separated(o.estimate);
  settings.outlier_threshold_sigma = o.outlier_sigma;
  settings.progress = terminal_progress();
  calib::StagedReport report;
  try {
    report = calib::calibrate_in_stages(&camera, &inputs.views, settings);
  } catch (const std::invalid_argument& e) {
    if (settings.progress) std::cerr << "\n";
    // An unknown group was caught by the option's check: what is left is about the observations.
    throw io::InputError(inputs.observations_file, 0, e.what());
  }
  if (settings.progress) std::cerr << "\n";

  calib::CalibrationOutcome outcome;
  outcome.inputs = inputs.description;
  outcome.camera = &camera;
  outcome.report = &report;
  outcome.views = &inputs.views;
  outcome.outlier_threshold_sigma = o.outlier_sigma;
  const std::string folder = report_folder_for(o.out);
  const calib::CalibrationReport& final = report.final;

  // A generic start of the kind named that does not converge where another kind does: the
  // images contradict --mirror (or --inner); said, and nothing written.
  if (!final.converged && start_camera.picture) {
    if (const std::string converges =
            other_kind_that_converges(o, *start_camera.picture, all_views, settings);
        !converges.empty()) {
      const bool detected = !o.images.empty();
      if (detected) fs::remove(o.corners);
      throw io::InputError(
          detected ? o.images : o.corners, 0,
          "from a generic start, " + kind_phrase(o.mirror, o.inner) +
              " did not converge on these " + (detected ? "images" : "corners") + " (" +
              final.message + "), where " + converges +
              (detected ? "; " + o.corners + ", the corners detected, removed" : "") +
              "; nothing written");
    }
  }
  // The report of a solve that did not converge is kept: its residuals per view show why.
  if (!final.converged) {
    const std::string note = write_report(folder, outcome);
    throw std::runtime_error("the calibration did not converge: " + final.message + "; " + o.out +
                             " was not written; the report is in " + folder +
                             (note.empty() ? "" : " (" + note + ")"));
  }

  calib::HeldOutResult held_out;
  if (!held.empty()) {
    try {
      held_out = calib::evaluate_held_out(camera, held);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(inputs.observations_file, 0, std::string("held-out ") + e.what());
    }
    outcome.held_out = &held_out;
  }
  calib::CrossValidation cross_validation;
  if (o.cross_validate > 0) {
    cross_validation =
        cross_validated(o, start, all_views, settings, inputs.observations_file);
    outcome.cross_validation = &cross_validation;
  }
  const int step = std::max(4, std::max(camera.image_width(), camera.image_height()) / 96);
  const calib::UncertaintyMap uncertainty = calib::projection_uncertainty(
      camera, report.estimated, inputs.views, final.joint_covariance, o.uncertainty_distance,
      step);
  const calib::UncertaintyMap uncertainty_camera_frame =
      calib::projection_uncertainty_in_camera_frame(camera, report.estimated, final.covariance,
                                                    o.uncertainty_distance, step);
  outcome.uncertainty = &uncertainty;
  outcome.uncertainty_camera_frame = &uncertainty_camera_frame;

  io::write_calibrated_camera_file(o.out, camera, {report.estimated, final.covariance});
  outcome.camera_file = o.out;
  print_written(o, outcome, folder, write_report(folder, outcome));
}

// The options that say what to calibrate from, and how they go together.
struct InputOptions {
  CLI::Option *camera, *images, *mirror, *image_size, *targets, *observations, *corners, *board,
      *spacing, *width_n, *height_n;
};

// What CLI11 checks itself: options that need or exclude others.
void relate(const InputOptions& in) {
  in.camera->excludes(in.mirror);
  in.mirror->excludes(in.camera);
  in.images->excludes(in.corners)->excludes(in.targets)->needs(in.spacing);
  in.corners->excludes(in.images);
  in.image_size->needs(in.mirror)->needs(in.corners);
  in.targets->needs(in.observations);
  in.observations->needs(in.targets);
  in.targets->excludes(in.corners);
  in.corners->excludes(in.targets);
  in.board->needs(in.corners);
  in.spacing->needs(in.width_n)->needs(in.height_n);
  in.width_n->needs(in.spacing);
  in.height_n->needs(in.spacing);
  in.board->excludes(in.spacing);
  in.spacing->excludes(in.board);
}

// What it cannot: one of several alternatives given, and combinations with no start.
void check_given(const InputOptions& in) {
  if (in.targets->count() == 0 && in.corners->count() == 0 && in.images->count() == 0)
    throw CLI::ValidationError("calibrate",
                               "give --targets with --observations, --corners with --board, "
                               "or --images with --object-spacing");
  if (in.camera->count() == 0 && in.mirror->count() == 0)
    throw CLI::ValidationError("calibrate", "give a starting --camera, or --mirror");
  if (in.mirror->count() > 0 && in.corners->count() > 0 && in.image_size->count() == 0)
    throw CLI::ValidationError("--mirror", "with --corners needs --image-size");
  if (in.mirror->count() > 0 && in.targets->count() > 0)
    throw CLI::ValidationError("--mirror", "surveyed targets need a starting --camera");
  if (in.spacing->count() > 0 && in.corners->count() == 0 && in.images->count() == 0)
    throw CLI::ValidationError("--object-spacing", "needs --corners or --images");
  if (in.corners->count() > 0 && in.board->count() == 0 && in.spacing->count() == 0)
    throw CLI::ValidationError("--corners", "needs --board, or --object-spacing with "
                                            "--object-width-n and --object-height-n");
}

}  // namespace

void add_calibrate_verb(CLI::App& app) {
  auto o = std::make_shared<CalibrateOptions>();
  CLI::App* verb = app.add_subcommand(
      "calibrate",
      "Calibrate from surveyed targets (the mirror-to-camera transform, the paper's method) or "
      "checkerboards (any camera parameters: their corners, or their raw images with --images, "
      "and from a starting --camera file or, with --mirror, from none); writes the camera file "
      "with its covariance and a report folder OUT-stem.report/ beside it. A solve that does not "
      "converge exits 1 and "
      "writes no camera file, but still writes its report folder (replacing an earlier one "
      "whole; status: NOT CONVERGED), to show why; but where a --mirror start does not "
      "converge and another generic kind does, the images contradict --mirror or --inner: it "
      "exits 2 naming the kind that converges, and writes nothing");
  auto* camera = verb->add_option("--camera", o->camera,
                                  "Starting camera file (the nominal design); or --mirror");
  auto* images = verb->add_option(
      "--images", o->images,
      "Board images (a folder of PNG or JPG files, or a video): the boards are detected as "
      "detect-corners does and their corners written beside --out as OUT-stem.corners.vnl "
      "(needs --object-spacing, --object-width-n and --object-height-n; where fewer than 3 are "
      "found, says what size of board the images show)");
  auto* mirror = verb->add_option("--mirror", o->mirror,
                                  "Without --camera: start from a generic mirror of this kind, "
                                  "placed by the mirror's picture in --images (or about the "
                                  "image's centre, around the corners, with --image-size)")
                     ->check(CLI::IsMember({"conic", "equiangular"}));
  verb->add_option("--inner", o->inner,
                   "With --mirror: the lens, a pinhole or a telecentric (orthographic) one")
      ->capture_default_str()
      ->check(CLI::IsMember({"pinhole", "orthographic"}));
  auto* image_size = verb->add_option("--image-size", o->image_size,
                                      "With --mirror and --corners: the images' size, WxH");
  auto* targets = verb->add_option("--targets", o->targets, "Surveyed targets, `# target x y z`");
  auto* observations = verb->add_option("--observations", o->observations,
                                        "Their observations, `# image target u v`");
  auto* corners = verb->add_option("--corners", o->corners,
                                   "Checkerboard corners, mrcal's `# filename x y level`");
  auto* board = verb->add_option("--board", o->board, "The board's points, `# index x y z`");
  auto* spacing = verb->add_option("--object-spacing", o->object_spacing,
                                   "Board point spacing, metres (instead of --board)")
                      ->check(positive_number());
  auto* width_n = verb->add_option("--object-width-n", o->object_width_n,
                                   "Board points across (a row of --corners' points; given "
                                   "swapped, the order of the corners says so)")
                      ->check(whole_number_between(2, 1000));
  auto* height_n = verb->add_option("--object-height-n", o->object_height_n, "Board points down")
                       ->check(whole_number_between(2, 1000));
  verb->add_option("--out", o->out, "Calibrated camera file to write")->required();
  auto* estimate = verb->add_option("--estimate", o->estimate,
                   "Comma-separated parameter groups: mirror-pose, mirror-shape, intrinsics, "
                   "distortion, all (with --mirror: mirror-pose,intrinsics,mirror-shape)")
      ->capture_default_str()
      ->check([](const std::string& text) {
        for (const std::string& group : comma_separated(text)) {
          if (group != "mirror-pose" && group != "mirror-shape" && group != "intrinsics" &&
              group != "distortion" && group != "all")
            return "unknown parameter group '" + group +
                   "' (expected mirror-pose, mirror-shape, intrinsics, distortion or all)";
        }
        return comma_separated(text).empty() ? std::string("no parameter group given")
                                             : std::string();
      });
  auto* holdout = verb->add_option("--holdout", o->holdout,
                   "Leave this many views (spread evenly) out, and report their RMS against the "
                   "calibration")
      ->check(whole_number_between(0));
  auto* cross_validate =
      verb->add_option("--cross-validate", o->cross_validate,
                       "Also cross-validate in K folds: fold f leaves out every K-th view from "
                       "the f-th, calibrates the rest from the same start, and measures the views "
                       "left out; the pooled held-out RMS is printed and in report.txt")
          ->check(whole_number_between(2));
  cross_validate->excludes(holdout);
  verb->add_option("--outlier-sigma", o->outlier_sigma,
                   "Reject a residual coordinate beyond this many residual sigmas")
      ->capture_default_str()
      ->check(number_between(1, 1000));
  verb->add_option("--uncertainty-distance", o->uncertainty_distance,
                   "Distance (metres) along each pixel's ray of the points in the projection-"
                   "uncertainty map")
      ->capture_default_str()
      ->check(positive_number());

  const InputOptions inputs{camera, images, mirror, image_size, targets, observations, corners,
                            board, spacing, width_n, height_n};
  relate(inputs);
  verb->callback([o, inputs, estimate] {
    check_given(inputs);
    o->estimate_given = estimate->count() > 0;
    run_calibrate(*o);
  });
}

}  // namespace omnisfm::app
