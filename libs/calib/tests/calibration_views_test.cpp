// Views from the input files, and the errors that name the file and line.

#include "omnisfm/calib/calibration_views.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "omnisfm/io/input_error.h"

namespace omnisfm::calib {
namespace {

std::string error_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const io::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(CalibrationViews, GroupTargetObservationsByImage) {
  const std::map<int, Eigen::Vector3d> targets = {{1, {1, 0, 0}}, {2, {0, 1, 0}}};
  const std::vector<io::TargetObservationRow> rows = {
      {10, 2, {5, 6}, 2}, {0, 1, {1, 2}, 3}, {10, 1, {7, 8}, 4}};
  const auto views = target_views(targets, rows, "obs.vnl");
  ASSERT_EQ(views.size(), 2u);
  EXPECT_EQ(views[0].name, "image 0");
  EXPECT_EQ(views[1].name, "image 10");
  EXPECT_EQ(views[1].point_ids, (std::vector<int>{2, 1}));
  EXPECT_EQ(views[1].points[0], Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(views[1].pixels[1], Eigen::Vector2d(7, 8));

  const std::vector<io::TargetObservationRow> unknown = {{0, 1, {1, 2}, 2}, {0, 7, {1, 2}, 3}};
  EXPECT_EQ(error_of([&] { target_views(targets, unknown, "obs.vnl"); }),
            "obs.vnl:3: target 7 has no survey entry in the targets file");
}

TEST(CalibrationViews, KeepDetectedCornersAndCheckTheBoard) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Eigen::Vector3d> board = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  std::vector<io::ImageCorners> images = {
      {"a.png", {{1, 1}, {nan, nan}, {3, 3}, {4, 4}}, {true, false, true, true}, 2, {}},
      {"empty.png", {}, {}, 6, {}},
  };
  const auto views = board_views(images, board, "corners.vnl", "board.vnl");
  ASSERT_EQ(views.size(), 1u);
  EXPECT_EQ(views[0].name, "a.png");
  EXPECT_EQ(views[0].point_ids, (std::vector<int>{0, 2, 3}));
  EXPECT_EQ(views[0].points[1], Eigen::Vector3d(0, 1, 0));

  images.push_back({"short.png", {{1, 1}, {2, 2}, {3, 3}}, {true, true, true}, 7, {}});
  EXPECT_EQ(error_of([&] { board_views(images, board, "corners.vnl", "board.vnl"); }),
            "corners.vnl:7: image 'short.png' has 3 corners but the board (board.vnl) has 4 "
            "points");
}

}  // namespace
}  // namespace omnisfm::calib
