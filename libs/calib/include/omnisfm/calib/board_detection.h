#pragma once
// Checkerboards found in raw catadioptric images, where the mirror bends them too much for a
// detector (mrgingham's and OpenCV's fail on them). Each image is looked at through virtual
// perspective views (perspective_view.h) at several azimuths, elevations and fields of view; in
// one of them the board is nearly straight and OpenCV's sector-based detector finds it. Of a board
// it finds larger than the grid asked for, the block the mirror squeezes least is taken, among
// those whose squares alternate as a checkerboard's (checkerboard_grid.h), ordered as a board of
// the grid's size comes. Its corners are mapped back
// through the view's table and refined on the raw image, so that no approximation of the views
// is left in them. A cheaper search for a board of any size (board_seen.h) goes first: an image
// whose views show no board near the grid's size is passed over by them, and the full search is
// made first in views that show a board at all. Where no view gives the board but some view
// shows a board, the raw image itself is searched last: where the mirror bends a board little
// it can be straighter there than in any view.

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "omnisfm/calib/perspective_view.h"
#include "omnisfm/io/checkerboard_files.h"

namespace omnisfm::calib {

struct BoardSearch {
  int view_size = 480;  // pixels
  std::vector<double> fields_of_view_deg{80, 100, 120};
  std::vector<double> elevations_deg{0, -20, 20};
  double azimuth_step_deg = 30;
  // Without a camera model: the elevations the mirror's picture spans, inner to outer radius.
  double elevation_span_deg = 100;
  // Without a camera model: corners must lie this fraction of its radius beyond the camera's own
  // reflection.
  double reflection_margin = 0.25;
};

struct DetectedBoard {
  // Raw-image pixels, width_n per row, rows in order: mrcal's board order, up to the board's
  // symmetries (which a rigid motion of the board explains).
  std::vector<Eigen::Vector2d> corners;
  std::optional<ViewDirection> view;  // where it was found; none: in the raw image itself
};

// An image's row block of corners.vnl: the board's corners, or none (`FILE - - -`).
io::ImageCorners image_corners(const std::string& name, const std::optional<DetectedBoard>& board);

class BoardDetector {
 public:
  // grid: points across (mrcal's object-width-n) and down (object-height-n). Without a model, the
  // generic views about `mirror`; with one, views through it.
  BoardDetector(const MirrorImage& mirror, cv::Size grid, const BoardSearch& search = {});
  BoardDetector(const camera::CatadioptricCamera& camera, cv::Size grid,
                const BoardSearch& search = {});

  // The whole board in an 8-bit grey raw image, or nothing. The views' tables are made the first
  // time each is needed and kept: they depend on the mirror only. *largest_seen, if given: the
  // largest board of any size the views searched showed (board_seen.h), an empty size where none;
  // where no board is found, every view was searched.
  std::optional<DetectedBoard> detect(const cv::Mat& raw_grey, cv::Size* largest_seen = nullptr);

 private:
  const PerspectiveView& view(std::size_t index);
  // Without a model: the shape of the views looking that way at any azimuth.
  const GenericViewShape& shape(const ViewDirection& direction);
  // The whole board in view `index`, rendered from raw_grey, by the full detector.
  std::optional<DetectedBoard> board_in_view(std::size_t index, const cv::Mat& rendered,
                                             const cv::Mat& raw_grey);
  // OpenCV's full detector on `image`: the board (of the grid, or larger), ordered clockwise as
  // the views show it. `mirrored`: the image is a mirror image of the views (the raw image is: a
  // view looks out at the scene, the raw image at its reflection).
  bool find_board(const cv::Mat& image, bool mirrored, std::vector<cv::Point2f>* found,
                  cv::Size* found_size) const;
  // The grid's block of a board found, in raw pixels, that the checks take, refined on the raw
  // image.
  std::optional<DetectedBoard> board_from(const std::vector<cv::Point2f>& found,
                                          cv::Size found_size, const cv::Mat& raw_grey) const;
  // Inside the image, and with the generic views inside the mirror's picture.
  bool usable(cv::Point2f corner, cv::Size image) const;

  std::optional<MirrorImage> mirror_;
  std::optional<camera::CatadioptricCamera> camera_;
  cv::Size grid_;
  BoardSearch search_;
  std::vector<ViewDirection> directions_;
  std::vector<std::optional<PerspectiveView>> views_;
  // Without a model: the views' shapes, one per field of view and elevation, made as the views
  // are and freed once all are.
  std::vector<GenericViewShape> shapes_;
};

}  // namespace omnisfm::calib
