#include "omnisfm/io/points_file.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "omnisfm/io/outliers_file.h"

namespace omnisfm::io {
namespace {

TEST(PointsFile, TableRowsReadBackExactly) {
  const Eigen::Vector3d a(0.1, -2.5e-7, 1234.5678901234567), b(-3, 0, 1.0 / 3);
  std::stringstream table;
  {
    PointsTableWriter writer(table);
    writer.point(7, a);
    writer.point(12, b);
  }
  std::string header;
  std::getline(table, header);
  EXPECT_EQ(header, "# track x y z");
  int track = 0;
  Eigen::Vector3d read;
  table >> track >> read.x() >> read.y() >> read.z();
  EXPECT_EQ(track, 7);
  EXPECT_EQ(read, a);  // round-trip precision
  table >> track >> read.x() >> read.y() >> read.z();
  EXPECT_EQ(track, 12);
  EXPECT_EQ(read, b);
}

TEST(PointsFile, PlyHeaderCountsThePointsThatFollow) {
  std::stringstream ply;
  write_ply_header(ply, 2);
  write_ply_point(ply, Eigen::Vector3d(1, 2, 3));
  write_ply_point(ply, Eigen::Vector3d(1.0 / 3, -0.5, 1e-9));
  const std::string text = ply.str();
  EXPECT_EQ(text.rfind("ply\nformat ascii 1.0\nelement vertex 2\n", 0), 0u) << text;
  const std::string body = text.substr(text.find("end_header\n") + 11);
  std::stringstream points(body);
  Eigen::Vector3d p;
  int count = 0;
  while (points >> p.x() >> p.y() >> p.z()) ++count;
  EXPECT_EQ(count, 2);
  EXPECT_EQ(p, Eigen::Vector3d(1.0 / 3, -0.5, 1e-9));
}

TEST(OutliersFile, RowsAreTrackAndFrame) {
  std::stringstream table;
  {
    OutliersTableWriter writer(table);
    writer.outlier(41, 1999);
  }
  EXPECT_EQ(table.str(), "# track frame\n41 1999\n");
}

}  // namespace
}  // namespace omnisfm::io
