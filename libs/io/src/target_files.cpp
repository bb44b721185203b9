#include "omnisfm/io/target_files.h"

#include <cmath>
#include <set>
#include <utility>

#include "omnisfm/io/input_error.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {
namespace {

int id_field(const VnlogTable& table, std::size_t row, std::size_t column,
             const std::string& name) {
  const double value = table.number(row, column);
  if (!std::isfinite(value) || value < 0 || value != std::floor(value) || value > 2e9) {
    throw InputError(table.file(), table.line(row),
                     "column '" + name + "': '" + table.text(row, column) +
                         "' is not a whole number from 0 to 2000000000");
  }
  return static_cast<int>(value);
}

double finite_field(const VnlogTable& table, std::size_t row, std::size_t column,
                    const std::string& name) {
  const double value = table.number(row, column);
  if (!std::isfinite(value)) {
    throw InputError(table.file(), table.line(row),
                     "column '" + name + "': '" + table.text(row, column) +
                         "' is not a finite number");
  }
  return value;
}

}  // namespace

std::map<int, Eigen::Vector3d> read_targets(const std::string& path) {
  const VnlogTable table = VnlogTable::read(path);
  const auto columns = table.columns({"target", "x", "y", "z"});
  std::map<int, Eigen::Vector3d> targets;
  std::map<int, int> line_of;
  for (std::size_t row = 0; row < table.num_rows(); ++row) {
    const int id = id_field(table, row, columns[0], "target");
    Eigen::Vector3d position;
    for (int k = 0; k < 3; ++k) {
      position[k] = finite_field(table, row, columns[k + 1], table.column_names()[columns[k + 1]]);
    }
    if (!targets.emplace(id, position).second) {
      throw InputError(path, table.line(row),
                       "target " + std::to_string(id) + " is surveyed twice (first on line " +
                           std::to_string(line_of[id]) + ")");
    }
    line_of[id] = table.line(row);
  }
  return targets;
}

std::vector<TargetObservationRow> read_target_observations(const std::string& path) {
  const VnlogTable table = VnlogTable::read(path);
  const auto columns = table.columns({"image", "target", "u", "v"});
  std::vector<TargetObservationRow> rows;
  std::set<std::pair<int, int>> seen;
  for (std::size_t row = 0; row < table.num_rows(); ++row) {
    TargetObservationRow o;
    o.image = id_field(table, row, columns[0], "image");
    o.target = id_field(table, row, columns[1], "target");
    const double u = finite_field(table, row, columns[2], "u");  // before the vector: either may throw
    const double v = finite_field(table, row, columns[3], "v");
    o.pixel = Eigen::Vector2d(u, v);
    o.line = table.line(row);
    if (!seen.insert({o.image, o.target}).second) {
      throw InputError(path, o.line,
                       "target " + std::to_string(o.target) + " is observed twice in image " +
                           std::to_string(o.image));
    }
    rows.push_back(o);
  }
  return rows;
}

}  // namespace omnisfm::io
