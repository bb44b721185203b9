#pragma once
// The reconstructed points as the sfm and run verbs write them: points.vnl (a row per track's
// point, world frame: track x y z) and points.ply (ASCII PLY, for point-cloud viewers such as
// MeshLab or CloudCompare, whose header needs the count before the first point).

#include <Eigen/Core>
#include <ostream>

#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {

// points.vnl, a row at a time.
class PointsTableWriter {
 public:
  explicit PointsTableWriter(std::ostream& out);
  void point(int track, const Eigen::Vector3d& point);

 private:
  VnlogWriter writer_;
};

// points.ply: the header for `count` points, then a write_ply_point per point (round-trip precision).
void write_ply_header(std::ostream& out, long count);
void write_ply_point(std::ostream& out, const Eigen::Vector3d& point);

}  // namespace omnisfm::io
