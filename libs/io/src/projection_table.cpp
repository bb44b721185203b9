#include "omnisfm/io/projection_table.h"

#include <cmath>
#include <limits>
#include <vector>

namespace omnisfm::io {
namespace {

constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();

}  // namespace

void write_projected_points(const camera::CatadioptricCamera& camera, const VnlogTable& points,
                            std::ostream& out) {
  const std::vector<std::size_t> xyz = points.columns({"x", "y", "z"});
  // Every row read before anything is written: a bad row leaves no partial table.
  std::vector<Eigen::Vector3d> rows;
  for (std::size_t row = 0; row < points.num_rows(); ++row)
    rows.emplace_back(points.number(row, xyz[0]), points.number(row, xyz[1]),
                      points.number(row, xyz[2]));
  VnlogWriter writer(out, {"u", "v"});
  for (const Eigen::Vector3d& X : rows) {
    Eigen::Vector2d pixel;
    if (X.allFinite() && camera.project(X, &pixel)) {
      writer.row({pixel.x(), pixel.y()});
    } else {
      writer.row({kMissing, kMissing});
    }
  }
}

void write_unprojected_pixels(const camera::CatadioptricCamera& camera, const VnlogTable& pixels,
                              std::ostream& out) {
  const std::vector<std::size_t> uv = pixels.columns({"u", "v"});
  std::vector<Eigen::Vector2d> rows;
  for (std::size_t row = 0; row < pixels.num_rows(); ++row)
    rows.emplace_back(pixels.number(row, uv[0]), pixels.number(row, uv[1]));
  VnlogWriter writer(out, {"ox", "oy", "oz", "dx", "dy", "dz"});
  for (const Eigen::Vector2d& pixel : rows) {
    Eigen::Vector3d origin, direction;
    if (pixel.allFinite() && camera.unproject(pixel, &origin, &direction)) {
      writer.row({origin.x(), origin.y(), origin.z(), direction.x(), direction.y(), direction.z()});
    } else {
      writer.row(std::vector<double>(6, kMissing));
    }
  }
}

}  // namespace omnisfm::io
