#include "board_images.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <stdexcept>

#include "omnisfm/calib/board_seen.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/track/image_sequence.h"
#include "terminal_progress.h"

namespace omnisfm::app {

namespace {

namespace fs = std::filesystem;

std::string image_name(const track::ImageSequence& sequence, const track::SequenceFrame& frame) {
  if (!frame.file.empty()) return fs::path(frame.file).filename().string();
  char index[16];
  std::snprintf(index, sizeof index, "-%06d", frame.index);
  return fs::path(sequence.path()).stem().string() + index;
}

// `board` either way round as the user would name it for `grid`: a count that matches stays in
// its place, else the fewer points across (as the real sets' boards are named).
cv::Size named_like(cv::Size board, cv::Size grid) {
  const cv::Size turned(board.height, board.width);
  if (board.width == grid.width || board.height == grid.height) return board;
  if (turned.width == grid.width || turned.height == grid.height) return turned;
  return board.width <= board.height ? board : turned;
}

std::string points(cv::Size size) {
  return std::to_string(size.width) + "x" + std::to_string(size.height);
}

}  // namespace

std::string boards_seen_note(const std::vector<cv::Size>& seen, cv::Size grid) {
  if (seen.empty()) return "";
  // A size seen either way round counts once; of sizes seen as often, the larger.
  std::map<std::pair<int, int>, int> images_showing;
  for (const cv::Size& size : seen)
    if (!size.empty()) ++images_showing[std::minmax(size.width, size.height)];
  if (images_showing.empty()) return "the images show no checkerboard";
  // The smallest grid the detector takes is what it grows on any fragment of a board; a board
  // seen larger anywhere is the better guess.
  const std::pair<int, int> fragment(3, 3);
  if (images_showing.size() > 1) images_showing.erase(fragment);
  if (images_showing.begin()->first == fragment)
    return "the images show a checkerboard, but no more than 3x3 points of it";
  auto most = images_showing.begin();
  for (auto it = images_showing.begin(); it != images_showing.end(); ++it)
    if (it->second > most->second ||
        (it->second == most->second &&
         it->first.first * it->first.second > most->first.first * most->first.second))
      most = it;
  const cv::Size board = named_like(cv::Size(most->first.first, most->first.second), grid);
  if (calib::holds(board, grid))
    return "the images show a board of " + points(board) + " points, but no whole " + points(grid) +
           " block of it could be taken";
  return "the images show a board of " + points(board) + " points (--object-width-n " +
         std::to_string(board.width) + " --object-height-n " + std::to_string(board.height) + ")";
}

calib::MirrorImage mirror_of(const std::string& images) {
  track::ImageSequence sequence(images);
  calib::MeanImage mean;
  track::SequenceFrame frame;
  while (sequence.next(&frame)) mean.add(frame.image);
  try {
    return calib::find_mirror_image(mean.mean());
  } catch (const std::runtime_error& e) {
    throw io::InputError(
        images, 0,
        std::string(e.what()) + "; searched on " +
            (mean.count() == 1 ? std::string("its one image")
                               : "the mean of its " + std::to_string(mean.count()) + " images"));
  }
}

cv::Size image_size_of(const std::string& images) {
  track::ImageSequence sequence(images);
  track::SequenceFrame frame;
  if (!sequence.next(&frame)) throw io::InputError(images, 0, "holds no image");
  return frame.image.size();
}

std::vector<io::ImageCorners> detect_boards(const std::string& images,
                                            calib::BoardDetector* detector,
                                            const std::function<void(const BoardImage&)>& each,
                                            std::optional<cv::Size> camera_size) {
  track::ImageSequence sequence(images);
  TerminalProgress progress("searched", "images");
  std::vector<io::ImageCorners> found;
  track::SequenceFrame frame;
  while (sequence.next(&frame)) {
    if (camera_size && frame.image.size() != *camera_size)
      throw io::InputError(frame.file.empty() ? images : frame.file, 0,
                           "the image is " + std::to_string(frame.image.cols) + "x" +
                               std::to_string(frame.image.rows) + " but the camera's is " +
                               std::to_string(camera_size->width) + "x" +
                               std::to_string(camera_size->height));
    BoardImage image{image_name(sequence, frame), frame.image, std::nullopt, {}};
    if (!io::fits_vnlog_field(image.name))
      throw io::InputError(frame.file, 0,
                           "has whitespace or '#' in its name, which corners.vnl cannot hold");
    image.board = detector->detect(frame.image, &image.board_seen);
    found.push_back(calib::image_corners(image.name, image.board));
    if (each) each(image);
    progress(static_cast<int>(found.size()), sequence.expected_frames());
  }
  if (const std::string lost = sequence.shortfall(); !lost.empty())
    std::cerr << "omnisfm: warning: " << io::printable_text(images + ": " + lost) << "\n";
  return found;
}

}  // namespace omnisfm::app
