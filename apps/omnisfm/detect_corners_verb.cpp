// omnisfm detect-corners: checkerboard corners in raw catadioptric images (calib/board_detection.h),
// written as mrcal's corners.vnl, with an overlay per image and a summary in a report folder.

#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "omnisfm/calib/board_detection.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/checkerboard_files.h"
#include "omnisfm/io/input_error.h"
#include "board_images.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

struct DetectCornersOptions {
  std::string images, camera, out;
  int width_n = 0, height_n = 0;
};

// The image with the mirror's circles (generic views only) and the board's corners drawn, the
// first corner marked, the rows in the detector's colours.
cv::Mat overlay(const cv::Mat& grey, const std::optional<calib::MirrorImage>& mirror,
                const std::optional<calib::DetectedBoard>& board, cv::Size grid) {
  cv::Mat colour;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  if (mirror) {
    const cv::Point2d centre(mirror->centre.x(), mirror->centre.y());
    cv::circle(colour, centre, static_cast<int>(mirror->inner_radius), cv::Scalar(255, 128, 0));
    cv::circle(colour, centre, static_cast<int>(mirror->outer_radius), cv::Scalar(255, 128, 0));
  }
  if (board) {
    std::vector<cv::Point2f> corners;
    for (const Eigen::Vector2d& c : board->corners)
      corners.emplace_back(static_cast<float>(c.x()), static_cast<float>(c.y()));
    cv::drawChessboardCorners(colour, grid, corners, true);
  }
  return colour;
}

struct Found {
  std::vector<io::ImageCorners> corners;
  int boards = 0;
};

// Each image searched, its overlay written into `report` as it goes, and the summary last.
Found detect_all(const DetectCornersOptions& o, const std::optional<calib::MirrorImage>& mirror,
                 calib::BoardDetector* detector, std::optional<cv::Size> camera_size,
                 const std::string& report) {
  const cv::Size grid(o.width_n, o.height_n);
  std::string summary = "# filename found view_azimuth_deg view_elevation_deg view_fov_deg\n";
  Found found;
  std::vector<cv::Size> seen;  // in the images without the grid's board
  found.corners = detect_boards(
      o.images, detector,
      [&](const BoardImage& image) {
        if (!image.board) seen.push_back(image.board_seen);
        char line[160];
        if (image.board) {
          ++found.boards;
          constexpr double kDeg = 180 / M_PI;
          if (const std::optional<calib::ViewDirection>& view = image.board->view)
            std::snprintf(line, sizeof line, " 1 %.0f %.0f %.0f\n", view->azimuth * kDeg,
                          view->elevation * kDeg, view->field_of_view * kDeg);
          else  // in the raw image itself
            std::snprintf(line, sizeof line, " 1 - - -\n");
        } else {
          std::snprintf(line, sizeof line, " 0 - - -\n");
        }
        summary += image.name + line;
        const std::string file = (fs::path(report) / (image.name + ".png")).string();
        if (!cv::imwrite(file, overlay(image.grey, mirror, image.board, grid)))
          throw std::runtime_error("cannot write " + file);
      },
      camera_size);
  // A board size that matches nothing is a mistake, not a result: said, and nothing written.
  if (found.boards == 0)
    throw io::InputError(
        o.images, 0,
        "no " + std::to_string(o.width_n) + "x" + std::to_string(o.height_n) +
            " board was found in " +
            (seen.size() == 1 ? std::string("its one image")
                              : "any of its " + std::to_string(seen.size()) + " images") +
            "; " + boards_seen_note(seen, grid));
  io::write_text_atomically((fs::path(report) / "summary.vnl").string(),
                            [&](std::ostream& out) { out << summary; });
  return found;
}

void run_detect_corners(const DetectCornersOptions& o) {
  const fs::path out = fs::absolute(o.out).lexically_normal();
  check_output_file(o.out, out);
  require_not_an_input(o.out, {o.camera, o.images});
  const fs::path folder = out.parent_path();
  const std::string report = (folder / (out.stem().string() + ".report")).string();
  if (fs::is_directory(folder)) io::check_folder_replaceable(report, {o.images, o.camera});
  std::optional<calib::MirrorImage> mirror;
  std::unique_ptr<calib::BoardDetector> detector;
  std::optional<cv::Size> camera_size;
  const cv::Size grid(o.width_n, o.height_n);
  if (o.camera.empty()) {
    try {
      mirror = mirror_of(o.images);
    } catch (const io::InputError& e) {
      // Where the mirror was not found in readable images, a camera file stands in for it.
      if (e.message().find("was not found") == std::string::npos) throw;
      throw io::InputError(e.file(), e.line(), e.message() + " (give --camera instead)");
    }
    detector = std::make_unique<calib::BoardDetector>(*mirror, grid);
  } else {
    const camera::CatadioptricCamera camera = load_camera(o.camera);
    camera_size = cv::Size(camera.image_width(), camera.image_height());
    detector = std::make_unique<calib::BoardDetector>(camera, grid);
  }
  Found found;
  in_folder_made_if_missing(folder, [&] {
    io::write_folder_atomically(report, [&](const std::string& dir) {
      found = detect_all(o, mirror, detector.get(), camera_size, dir);
    });
    io::write_corners(out.string(), found.corners);
  });
  if (mirror)
    std::printf("mirror: centre (%.1f, %.1f), its picture %.0f-%.0f px from it\n",
                mirror->centre.x(), mirror->centre.y(), mirror->inner_radius,
                mirror->outer_radius);
  std::printf("found a %dx%d board in %d of %zu images; wrote %s, and the overlays and summary.vnl "
              "in %s\n",
              o.width_n, o.height_n, found.boards, found.corners.size(), o.out.c_str(),
              report.c_str());
  finish_stdout();
}

}  // namespace

void add_detect_corners_verb(CLI::App& app) {
  auto o = std::make_shared<DetectCornersOptions>();
  CLI::App* verb = app.add_subcommand(
      "detect-corners",
      "Find checkerboard corners in raw catadioptric images: each image is looked at through "
      "virtual perspective views (through the camera model with --camera, else through a generic "
      "one about the mirror's circles, found on the mean image), where the board is nearly "
      "straight for OpenCV's detector (and, where no view holds the whole board, the raw image "
      "itself); the corners are refined on the raw image. Writes mrcal's "
      "corners.vnl (`FILE - - -` where no whole board was found) and a report folder "
      "OUT-stem.report/ beside it: an overlay PNG per image and summary.vnl (which view found each "
      "board). Where no image holds the board asked for, says what size of board they show, "
      "writes nothing and exits 2");
  verb->add_option("--images", o->images,
                   "A folder of PNG or JPG images (taken in file-name order) or a video file")
      ->required();
  verb->add_option("--object-width-n", o->width_n, "Board points across (inner corners)")
      ->required()
      ->check(whole_number_between(3, 1000));
  verb->add_option("--object-height-n", o->height_n, "Board points down (inner corners)")
      ->required()
      ->check(whole_number_between(3, 1000));
  verb->add_option("--camera", o->camera,
                   "Camera file whose model straightens the views (default: none, the generic "
                   "views)");
  verb->add_option("--out", o->out, "Corners file to write (mrcal's corners.vnl)")->required();
  verb->callback([o] { run_detect_corners(*o); });
}

}  // namespace omnisfm::app
