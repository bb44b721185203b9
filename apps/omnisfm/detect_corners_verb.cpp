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
#include "omnisfm/track/image_sequence.h"
#include "terminal_progress.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

struct DetectCornersOptions {
  std::string images, camera, out;
  int width_n = 0, height_n = 0;
};

// An image's name in corners.vnl: its file's name, or for a video's frame the video's stem and the
// frame's index.
std::string image_name(const track::ImageSequence& sequence, const track::SequenceFrame& frame) {
  if (!frame.file.empty()) return fs::path(frame.file).filename().string();
  char index[16];
  std::snprintf(index, sizeof index, "-%06d", frame.index);
  return fs::path(sequence.path()).stem().string() + index;
}

// Where the mirror is, from the mean of every image.
calib::MirrorImage mirror_of(const std::string& images) {
  track::ImageSequence sequence(images);
  calib::MeanImage mean;
  track::SequenceFrame frame;
  while (sequence.next(&frame)) mean.add(frame.image);
  try {
    return calib::find_mirror_image(mean.mean());
  } catch (const std::runtime_error& e) {
    throw io::InputError(images, 0,
                         std::string(e.what()) + " on the mean of its " +
                             std::to_string(mean.count()) + " images (give --camera instead)");
  }
}

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
                 calib::BoardDetector* detector, const std::string& report) {
  const cv::Size grid(o.width_n, o.height_n);
  track::ImageSequence sequence(o.images);
  TerminalProgress progress("searched", "images");
  std::string summary = "# filename found view_azimuth_deg view_elevation_deg view_fov_deg\n";
  Found found;
  track::SequenceFrame frame;
  while (sequence.next(&frame)) {
    const std::string name = image_name(sequence, frame);
    if (name.find_first_of(" \t\r\n\v\f") != std::string::npos)
      throw io::InputError(frame.file, 0, "has whitespace in its name, which corners.vnl cannot hold");
    const std::optional<calib::DetectedBoard> board = detector->detect(frame.image);
    io::ImageCorners image{name, {}, {}, 0};
    char line[160];
    if (board) {
      ++found.boards;
      image.pixels = board->corners;
      image.detected.assign(board->corners.size(), true);
      constexpr double kDeg = 180 / M_PI;
      std::snprintf(line, sizeof line, " 1 %.0f %.0f %.0f\n", board->view.azimuth * kDeg,
                    board->view.elevation * kDeg, board->view.field_of_view * kDeg);
    } else {
      image.pixels.assign(1, Eigen::Vector2d::Constant(NAN));
      image.detected.assign(1, false);
      std::snprintf(line, sizeof line, " 0 - - -\n");
    }
    summary += name + line;
    found.corners.push_back(std::move(image));
    const std::string overlay_file = (fs::path(report) / (name + ".png")).string();
    if (!cv::imwrite(overlay_file, overlay(frame.image, mirror, board, grid)))
      throw std::runtime_error("cannot write " + overlay_file);
    progress(static_cast<int>(found.corners.size()), sequence.expected_frames());
  }
  io::write_text_atomically((fs::path(report) / "summary.vnl").string(),
                            [&](std::ostream& out) { out << summary; });
  return found;
}

void run_detect_corners(const DetectCornersOptions& o) {
  const fs::path out = fs::absolute(o.out).lexically_normal();
  if (fs::is_directory(out)) throw io::InputError(o.out, 0, "is a folder; give the corners file's name");
  // The corners file's folder is made when missing (and goes again on failure), as track makes
  // its tracks file's.
  const fs::path folder = out.parent_path();
  require_writable_folder(o.out, fs::exists(folder) ? folder : folder.parent_path());
  std::optional<calib::MirrorImage> mirror;
  std::unique_ptr<calib::BoardDetector> detector;
  const cv::Size grid(o.width_n, o.height_n);
  if (o.camera.empty()) {
    mirror = mirror_of(o.images);
    detector = std::make_unique<calib::BoardDetector>(*mirror, grid);
  } else {
    detector = std::make_unique<calib::BoardDetector>(load_camera(o.camera), grid);
  }
  const std::string report = (folder / (out.stem().string() + ".report")).string();
  Found found;
  const bool made = fs::create_directory(folder);
  try {
    io::write_folder_atomically(report, [&](const std::string& dir) {
      found = detect_all(o, mirror, detector.get(), dir);
    });
    io::write_corners(out.string(), found.corners);
  } catch (...) {
    std::error_code ignored;
    if (made) fs::remove_all(folder, ignored);
    throw;
  }
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
      "straight for OpenCV's detector; the corners are refined on the raw image. Writes mrcal's "
      "corners.vnl (`FILE - - -` where no whole board was found) and a report folder OUT-stem.report/ "
      "beside it: an overlay PNG per image and summary.vnl (which view found each board)");
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
