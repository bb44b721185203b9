#include "omnisfm/io/checkerboard_files.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "io_test_folder.h"
#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

using CheckerboardFiles = TestFolder;

TEST_F(CheckerboardFiles, ReadsCornersKeepingMissingOnesInBoardOrder) {
  const auto images = read_corners(write("corners.vnl",
                                         "# filename x y level\n"
                                         "a.png 1 2 0\n"
                                         "a.png 3 4 -\n"      // culled: missing
                                         "a.png 5 6 -1\n"     // not detected: missing
                                         "a.png 7 8 1\n"
                                         "b.png - - -\n"      // no board at all
                                         "c.png 9 10 0\n"
                                         "c.png - - -\n"));   // a missing corner
  ASSERT_EQ(images.size(), 3u);
  EXPECT_EQ(images[0].filename, "a.png");
  ASSERT_EQ(images[0].pixels.size(), 4u);
  EXPECT_EQ(images[0].detected, (std::vector<bool>{true, false, false, true}));
  EXPECT_EQ(images[0].pixels[3], Eigen::Vector2d(7, 8));
  EXPECT_TRUE(std::isnan(images[0].pixels[1].x()));
  EXPECT_EQ(images[0].num_detected(), 2);
  EXPECT_EQ(images[0].first_line, 2);
  EXPECT_TRUE(images[1].pixels.empty());
  EXPECT_EQ(images[2].detected, (std::vector<bool>{true, false}));
}

TEST_F(CheckerboardFiles, WrittenCornersReadBackTheSame) {
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<ImageCorners> written{
      {"a.png", {{1.25, 2.5}, {kNan, kNan}, {7.125, 8}}, {true, false, true}, 0, {}},
      {"b.png", {}, {}, 0, {}},  // no board
      {"c.png", {{9, 10}}, {true}, 0, {}}};
  const std::string path = write("corners.vnl", "");
  write_corners(path, written);
  const auto read = read_corners(path);
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(read[0].detected, written[0].detected);
  EXPECT_EQ(read[0].pixels[0], written[0].pixels[0]);
  EXPECT_EQ(read[0].pixels[2], written[0].pixels[2]);
  EXPECT_EQ(read[1].filename, "b.png");
  EXPECT_EQ(read[1].num_detected(), 0);
  EXPECT_EQ(read[2].pixels[0], Eigen::Vector2d(9, 10));
  EXPECT_THROW(write_corners(path, {{"with space.png", {{1, 2}}, {true}, 0, {}}}),
               std::invalid_argument);
  EXPECT_EQ(read_corners(path).size(), 3u);  // the file as it was
}

TEST_F(CheckerboardFiles, RejectsInterleavedImagesAndBadNumbers) {
  const std::string interleaved =
      write("i.vnl", "# filename x y level\na 1 2 0\nb 1 2 0\na 3 4 0\n");
  EXPECT_NE(input_error_of([&] { read_corners(interleaved); })
                .find("i.vnl:4: the rows of image 'a' are not contiguous"),
            std::string::npos);
  const std::string bad = write("bad.vnl", "# filename x y level\na 1 - 0\n");
  EXPECT_NE(input_error_of([&] { read_corners(bad); }).find("bad.vnl:2:"), std::string::npos);
}

TEST_F(CheckerboardFiles, ReadsBoards) {
  const auto board = read_board(write("board.vnl",
                                      "# index x y z\n0 0 0 0\n1 0 0.03 0\n2 0.03 0 0\n"
                                      "3 0.03 0.03 0\n"));
  ASSERT_EQ(board.size(), 4u);
  EXPECT_EQ(board[1], Eigen::Vector3d(0, 0.03, 0));
  const std::string skipped = write("s.vnl", "# index x y z\n0 0 0 0\n2 0 0 0\n");
  EXPECT_NE(input_error_of([&] { read_board(skipped); }).find("s.vnl:3: column 'index': expected 1"),
            std::string::npos);
  const std::string tiny = write("t.vnl", "# index x y z\n0 0 0 0\n");
  EXPECT_NE(input_error_of([&] { read_board(tiny); }).find("at least 4 points"), std::string::npos);
  for (const char* flat : {"# index x y z\n0 0 0 0\n1 0 0 0\n2 0 0 0\n3 0 0 0\n",
                           "# index x y z\n0 0 0 0\n1 0.1 0 0\n2 0.2 0 0\n3 0.3 0 0\n"}) {
    const std::string line = write("l.vnl", flat);
    EXPECT_NE(input_error_of([&] { read_board(line); })
                  .find("l.vnl: the board's points lie on one "
                        "line or at one point"),
              std::string::npos)
        << flat;
  }
}

TEST(RegularBoard, FollowsMrcalsPointOrder) {
  const auto board = regular_board(0.02, 3, 2);
  ASSERT_EQ(board.size(), 6u);
  EXPECT_TRUE(board[1].isApprox(Eigen::Vector3d(0.02, 0, 0)));
  EXPECT_TRUE(board[3].isApprox(Eigen::Vector3d(0, 0.02, 0)));
  EXPECT_THROW(regular_board(0, 3, 2), std::invalid_argument);
  EXPECT_THROW(regular_board(0.02, 1, 2), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::io
