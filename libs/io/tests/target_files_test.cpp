#include "omnisfm/io/target_files.h"

#include <gtest/gtest.h>

#include "io_test_folder.h"
#include "omnisfm/io/input_error.h"

namespace omnisfm::io {
namespace {

using TargetFiles = TestFolder;

TEST_F(TargetFiles, ReadsTargetsAndObservations) {
  const auto targets = read_targets(write("targets.vnl", "# target x y z\n3 1 2 3\n0 -1 0.5 2\n"));
  ASSERT_EQ(targets.size(), 2u);
  EXPECT_EQ(targets.at(3), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(targets.at(0), Eigen::Vector3d(-1, 0.5, 2));

  const auto rows = read_target_observations(
      write("observations.vnl", "# image target u v\n0 3 10.5 20\n## comment\n4 0 1 2\n"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].image, 4);
  EXPECT_EQ(rows[1].target, 0);
  EXPECT_EQ(rows[1].pixel, Eigen::Vector2d(1, 2));
  EXPECT_EQ(rows[1].line, 4);
}

TEST_F(TargetFiles, ErrorsNameTheFileAndLine) {
  const std::string duplicate = write("t.vnl", "# target x y z\n1 0 0 0\n1 1 1 1\n");
  EXPECT_NE(input_error_of([&] { read_targets(duplicate); }).find("t.vnl:3: target 1 is surveyed twice"),
            std::string::npos);
  const std::string missing = write("m.vnl", "# target x y z\n1 0 - 0\n");
  EXPECT_NE(input_error_of([&] { read_targets(missing); }).find("m.vnl:2: column 'y'"),
            std::string::npos);
  const std::string fractional = write("o.vnl", "# image target u v\n0.5 1 0 0\n");
  EXPECT_NE(input_error_of([&] { read_target_observations(fractional); }).find("o.vnl:2: column 'image'"),
            std::string::npos);
  const std::string twice = write("o2.vnl", "# image target u v\n0 1 0 0\n0 1 2 2\n");
  EXPECT_NE(input_error_of([&] { read_target_observations(twice); })
                .find("o2.vnl:3: target 1 is observed twice in image 0"),
            std::string::npos);
  const std::string no_column = write("o3.vnl", "# image u v\n0 0 0\n");
  EXPECT_NE(input_error_of([&] { read_target_observations(no_column); }).find("no column 'target'"),
            std::string::npos);
}

}  // namespace
}  // namespace omnisfm::io
