#include "omnisfm/io/points_file.h"

#include "omnisfm/io/number_text.h"

namespace omnisfm::io {

PointsTableWriter::PointsTableWriter(std::ostream& out) : writer_(out, {"track", "x", "y", "z"}) {}

void PointsTableWriter::point(int track, const Eigen::Vector3d& point) {
  writer_.row({double(track), point.x(), point.y(), point.z()});
}

void write_ply_header(std::ostream& out, long count) {
  out << "ply\nformat ascii 1.0\nelement vertex " << count
      << "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
}

void write_ply_point(std::ostream& out, const Eigen::Vector3d& point) {
  out << format_double(point.x()) << ' ' << format_double(point.y()) << ' '
      << format_double(point.z()) << '\n';
}

}  // namespace omnisfm::io
