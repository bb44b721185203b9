#include "omnisfm/io/tum_trajectory.h"

#include <gtest/gtest.h>

#include <fstream>

#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(TumTrajectory, WriteThenReadGivesThePoses) {
  std::vector<StampedPose> poses(3);
  for (int i = 0; i < 3; ++i) {
    poses[i].timestamp = 0.5 * i;
    poses[i].world_from_cam.linear() =
        Eigen::AngleAxisd(0.3 * i + 0.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    poses[i].world_from_cam.translation() << i, -0.25 * i, 1.0 / 3;
  }
  const std::string path = ::testing::TempDir() + "/trajectory.tum";
  write_tum_trajectory(path, poses);
  const auto back = read_tum_trajectory(path);
  ASSERT_EQ(back.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(back[i].timestamp, poses[i].timestamp);
    EXPECT_EQ(back[i].world_from_cam.translation(), poses[i].world_from_cam.translation());
    EXPECT_LT((back[i].world_from_cam.linear() - poses[i].world_from_cam.linear()).norm(), 1e-15);
  }
}

TEST(TumTrajectory, MalformedLinesNameFileAndLine) {
  auto expect_error = [](const std::string& text, const std::string& what, int line) {
    const std::string path = write_file("bad.tum", text);
    try {
      read_tum_trajectory(path);
      FAIL() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), line);
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("# header\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n", "expected 8 fields", 3);
  expect_error("0 0 0 0 0 0 0 1\n1 0 x 0 0 0 0 1\n", "'x'", 2);
  expect_error("0 0 0 0 0 0 0 2\n", "unit length", 1);
  expect_error("1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", "increase", 2);
  EXPECT_THROW(read_tum_trajectory("/nonexistent/x.tum"), InputError);
}

}  // namespace
}  // namespace omnisfm::io
