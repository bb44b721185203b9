#include "omnisfm/calib/board_detection.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "omnisfm/calib/board_seen.h"
#include "omnisfm/calib/checkerboard_grid.h"

namespace omnisfm::calib {

namespace {

constexpr double kRadiansPerDegree = M_PI / 180;
// A block is taken only where this share of its pairs of neighbouring squares alternate as a
// checkerboard's (checkerboard_grid.h): every block of the boards found in the vmr,
// paracatadioptric and Kaidan sets scores 1, a grid that skipped rows of a Kaidan board 0.42.
constexpr double kMinAlternatingShare = 0.8;
// And only where, along each of its edges, this share of the squares just beyond it alternate
// with each other and with the block's own (checkerboard_grid.h): every edge of the real sets'
// blocks scores 1; a grid whose edge ran along a board's border, which a rendered board showed
// through the parabolic rig 10 px off, about a quarter.
constexpr double kMinEdgeShare = 0.5;
// How many rows or columns short of the grid the cheap search may see a board and still have the
// image searched (detect()).
constexpr int kRowsShort = 2;

std::vector<ViewDirection> view_directions(const BoardSearch& search) {
  std::vector<ViewDirection> directions;
  for (double fov : search.fields_of_view_deg)
    for (double azimuth = 0; azimuth < 360 - 1e-9; azimuth += search.azimuth_step_deg)
      for (double elevation : search.elevations_deg)
        directions.push_back({azimuth * kRadiansPerDegree, elevation * kRadiansPerDegree,
                              fov * kRadiansPerDegree});
  return directions;
}

// Half the refinement window: big enough to hold the corner's saddle, small enough to stay inside
// its own squares (a 40 % of the closest neighbour's distance).
int refinement_half_window(const std::vector<cv::Point2f>& corners, int width_n) {
  return std::clamp(static_cast<int>(0.4 * closest_corner_spacing(corners, width_n)), 2, 10);
}

}  // namespace

io::ImageCorners image_corners(const std::string& name, const std::optional<DetectedBoard>& board) {
  io::ImageCorners corners{name, {}, {}, 0, {}};
  if (board) {
    corners.pixels = board->corners;
    corners.detected.assign(corners.pixels.size(), true);
  } else {
    corners.pixels.assign(1, Eigen::Vector2d::Constant(NAN));
    corners.detected.assign(1, false);
  }
  return corners;
}

BoardDetector::BoardDetector(const MirrorImage& mirror, cv::Size grid, const BoardSearch& search)
    : mirror_(mirror), grid_(grid), search_(search), directions_(view_directions(search)),
      views_(directions_.size()) {}

BoardDetector::BoardDetector(const camera::CatadioptricCamera& camera, cv::Size grid,
                             const BoardSearch& search)
    : camera_(camera), grid_(grid), search_(search), directions_(view_directions(search)),
      views_(directions_.size()) {}

bool BoardDetector::usable(cv::Point2f corner, cv::Size image) const {
  if (corner.x < 0 || corner.y < 0 || corner.x > image.width - 1 || corner.y > image.height - 1)
    return false;
  if (!mirror_) {  // through the model: a pixel that sees the mirror (a raw image's corner may not)
    Eigen::Vector3d origin, direction;
    return camera_->unproject(Eigen::Vector2d(corner.x, corner.y), &origin, &direction);
  }
  // Next to the camera's own reflection the squares are squeezed and merge with its dark disc, and
  // a board larger than the grid asked for is better taken a row further out.
  const double r = (Eigen::Vector2d(corner.x, corner.y) - mirror_->centre).norm();
  return r > (1 + search_.reflection_margin) * mirror_->inner_radius && r < mirror_->outer_radius;
}

const GenericViewShape& BoardDetector::shape(const ViewDirection& direction) {
  for (const GenericViewShape& known : shapes_)
    if (known.elevation() == direction.elevation &&
        known.field_of_view() == direction.field_of_view)
      return known;
  return shapes_.emplace_back(*mirror_, search_.elevation_span_deg * kRadiansPerDegree,
                              direction.elevation, direction.field_of_view, search_.view_size);
}

const PerspectiveView& BoardDetector::view(std::size_t index) {
  if (!views_[index]) {
    if (camera_)
      views_[index].emplace(*camera_, directions_[index], search_.view_size);
    else
      views_[index].emplace(shape(directions_[index]), directions_[index].azimuth);
    // Once every view is made, their shapes' tables (50 MB) are not needed again.
    if (std::all_of(views_.begin(), views_.end(), [](const auto& v) { return v.has_value(); }))
      shapes_ = std::vector<GenericViewShape>();
  }
  return *views_[index];
}

std::optional<DetectedBoard> BoardDetector::detect(const cv::Mat& raw_grey,
                                                   cv::Size* largest_seen) {
  CV_Assert(raw_grey.type() == CV_8UC1);
  // OpenCV's quick check (4.3 ms a 480 px view on the vmr set) orders the search: the views it
  // likes first, then the rest, as it misses a third of the boards the full detector (0.17-0.24 s
  // on a view holding the board; bench/detect_bench.cpp) finds. The order is made only as far as
  // the search walks it: where the board is found in a view the check liked, the views after it
  // are neither rendered nor checked, and the search is the same.
  const std::size_t n = directions_.size();
  std::vector<cv::Mat> rendered(n);
  const auto rendered_view = [&](std::size_t index) -> const cv::Mat& {
    if (rendered[index].empty()) rendered[index] = view(index).render(raw_grey);
    return rendered[index];
  };
  std::vector<std::size_t> order, disliked;
  std::size_t checked = 0;
  const auto view_at = [&](std::size_t k) {  // the order's k-th view; n beyond its end
    while (order.size() <= k && checked < n) {
      const std::size_t index = checked++;
      (cv::checkChessboard(rendered_view(index), grid_) ? order : disliked).push_back(index);
      if (checked == n) order.insert(order.end(), disliked.begin(), disliked.end());
    }
    return k < order.size() ? order[k] : n;
  };
  // The cheap detector (board_seen.h, a third of the full one's time) goes first, for two
  // things. An image where no view shows a board within kRowsShort rows of holding the grid is
  // passed over: it may grow a board a row short (one paracatadioptric 6 x 8 board is 6 x 7 at
  // most in every view), never more on the real sets, and the second row is margin for rigs not
  // measured (the mistyped sizes measured stay beyond it; a row and a column more would not keep
  // 9 x 7 asked of the 6 x 8 board beyond). And the full
  // detector, in the order above, searches the views where it sees a board at all first: in each
  // of the 92 vmr views where the full one found a board, it saw one, if only 3 x 3 of it. Where
  // none of those gives the board, the other views are searched too, so that an image the board
  // may be in costs at worst what it did before the cheap search. An image without the board
  // costs the cheap search in every view instead of the full one (measured 5 s instead of 15-24
  // a real image, on a busy machine), and where some view showed part of a board, the raw
  // image's full search below (0.7-1 s at 1024 x 768 to 1280 x 1024).
  std::vector<cv::Size> seen(directions_.size(), cv::Size(-1, -1));  // -1: not yet looked at
  const auto seen_in = [&](std::size_t index) {
    if (seen[index].width < 0) seen[index] = board_seen(rendered_view(index));
    return seen[index];
  };
  bool grid_seen = false;
  for (std::size_t k = 0, index = view_at(0); !grid_seen && index < n; index = view_at(++k)) {
    const cv::Size board = seen_in(index);
    grid_seen = holds(board + cv::Size(kRowsShort, 0), grid_) ||
                holds(board + cv::Size(0, kRowsShort), grid_);
  }
  std::optional<DetectedBoard> board;
  if (grid_seen)
    for (const bool with_a_board_seen : {true, false}) {
      for (std::size_t k = 0, index = view_at(0); index < n; index = view_at(++k))
        if (seen_in(index).empty() != with_a_board_seen &&
            (board = board_in_view(index, rendered_view(index), raw_grey)))
          break;
      if (board) break;
    }
  // Where no view gives it, the raw image itself: a board far out in a mirror that bends little
  // there can be straighter in it than in any generic view (the omnidir tutorial's rig: one of
  // its 18 boards, found in no view, the views showing at most 6 x 6 of its 9 x 6). Searched
  // where some view showed a board at all; the cheap search is no guide on a raw image (4 x 5 of
  // that board), and the full one costs 1-2 s on 1280 x 960.
  const bool board_in_some_view =
      std::any_of(seen.begin(), seen.end(), [](cv::Size s) { return s.width > 0; });
  if (!board && board_in_some_view) {
    std::vector<cv::Point2f> found;
    cv::Size found_size;
    if (find_board(raw_grey, true, &found, &found_size))
      board = board_from(found, found_size, raw_grey);
  }
  if (largest_seen) {
    *largest_seen = cv::Size();
    for (const cv::Size& size : seen)
      if (size.width > 0 && size.area() > largest_seen->area()) *largest_seen = size;
  }
  return board;
}

std::optional<DetectedBoard> BoardDetector::board_in_view(std::size_t index,
                                                          const cv::Mat& rendered,
                                                          const cv::Mat& raw_grey) {
  std::vector<cv::Point2f> found;
  cv::Size found_size;
  if (!find_board(rendered, false, &found, &found_size)) return std::nullopt;
  const PerspectiveView& v = view(index);
  for (cv::Point2f& c : found) c = v.raw_pixel(c);
  std::optional<DetectedBoard> board = board_from(found, found_size, raw_grey);
  if (board) board->view = directions_[index];
  return board;
}

bool BoardDetector::find_board(const cv::Mat& image, bool mirrored, std::vector<cv::Point2f>* found,
                               cv::Size* found_size) const {
  cv::Mat meta;  // the board found, a cell per corner: its size
  if (!cv::findChessboardCornersSB(
          image, grid_, *found,
          cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY | cv::CALIB_CB_LARGER, meta))
    return false;
  *found_size = meta.empty() ? grid_ : cv::Size(meta.cols, meta.rows);
  if (static_cast<std::size_t>(found_size->area()) != found->size()) return false;
  // Clockwise as a view shows the board: in a mirror image of the views, counter-clockwise.
  if (mirrored)
    for (cv::Point2f& c : *found) c.x = -c.x;
  order_clockwise(found, *found_size);
  if (mirrored)
    for (cv::Point2f& c : *found) c.x = -c.x;
  return true;
}

std::optional<DetectedBoard> BoardDetector::board_from(const std::vector<cv::Point2f>& found,
                                                       cv::Size found_size,
                                                       const cv::Mat& raw_grey) const {
  // Of a board larger than the grid (OpenCV returns one only where it holds the grid turned a
  // quarter too), the block whose squares the mirror squeezes least: next to the camera's
  // reflection they shrink to a few pixels, where a corner is easily a square off (on the
  // Kaidan set, blocks taken as found fitted at 2.6 px, the least squeezed at 0.33).
  std::vector<cv::Point2f> corners;
  double widest = 0;
  for (std::vector<cv::Point2f>& block : grid_blocks(found, found_size, grid_)) {
    if (!std::all_of(block.begin(), block.end(),
                     [&](const cv::Point2f& c) { return usable(c, raw_grey.size()); }))
      continue;
    const SquareChecks squares = check_squares(raw_grey, block, grid_.width);
    if (squares.alternating < kMinAlternatingShare || squares.weakest_edge < kMinEdgeShare)
      continue;
    if (const double spacing = closest_corner_spacing(block, grid_.width); spacing > widest) {
      widest = spacing;
      corners = std::move(block);
    }
  }
  if (corners.empty()) return std::nullopt;
  const int half = refinement_half_window(corners, grid_.width);
  cv::cornerSubPix(raw_grey, corners, cv::Size(half, half), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
  DetectedBoard board;
  for (const cv::Point2f& c : corners) board.corners.emplace_back(c.x, c.y);
  return board;
}

}  // namespace omnisfm::calib
