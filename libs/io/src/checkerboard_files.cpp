#include "omnisfm/io/checkerboard_files.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <ostream>
#include <stdexcept>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {

int ImageCorners::num_detected() const {
  return static_cast<int>(std::count(detected.begin(), detected.end(), true));
}

void write_corners(const std::string& path, const std::vector<ImageCorners>& images) {
  for (const ImageCorners& image : images)
    if (image.filename.empty() ||
        std::any_of(image.filename.begin(), image.filename.end(),
                    [](unsigned char c) { return std::isspace(c) != 0; }))
      throw std::invalid_argument("write_corners: '" + image.filename +
                                  "' cannot be a vnlog column (empty, or with whitespace)");
  write_text_atomically(path, [&](std::ostream& out) {
    out << "# filename x y level\n";
    char row[96];
    for (const ImageCorners& image : images) {
      if (image.num_detected() == 0) {
        out << image.filename << " - - -\n";
        continue;
      }
      for (std::size_t k = 0; k < image.pixels.size(); ++k) {
        if (image.detected[k])
          std::snprintf(row, sizeof row, " %.4f %.4f 0\n", image.pixels[k].x(), image.pixels[k].y());
        else
          std::snprintf(row, sizeof row, " - - -\n");
        out << image.filename << row;
      }
    }
  });
}

std::vector<ImageCorners> read_corners(const std::string& path) {
  const VnlogTable table = VnlogTable::read(path);
  const auto columns = table.columns({"filename", "x", "y", "level"});
  std::vector<ImageCorners> images;
  std::map<std::string, std::size_t> index_of;
  constexpr double kMissing = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t row = 0; row < table.num_rows(); ++row) {
    const std::string& filename = table.text(row, columns[0]);
    const auto found = index_of.find(filename);
    if (found == index_of.end()) {
      index_of[filename] = images.size();
      images.push_back({filename, {}, {}, table.line(row), {}});
    } else if (found->second != images.size() - 1) {
      throw InputError(path, table.line(row),
                       "the rows of image '" + filename + "' are not contiguous (it began on line " +
                           std::to_string(images[found->second].first_line) + ")");
    }
    ImageCorners& image = images.back();
    const std::string& x_text = table.text(row, columns[1]);
    const std::string& y_text = table.text(row, columns[2]);
    const std::string& level_text = table.text(row, columns[3]);
    double level = 0;
    const bool has_level = !VnlogTable::is_missing(level_text) &&
                           !(VnlogTable::is_missing(x_text) && VnlogTable::is_missing(y_text));
    if (has_level && !parse_double(level_text, &level)) {
      throw InputError(path, table.line(row), "column 'level': '" + level_text + "' is not a number");
    }
    const bool detected = has_level && level >= 0;
    Eigen::Vector2d pixel(kMissing, kMissing);
    if (detected) {
      const double x = table.number(row, columns[1]);  // before the vector: either may throw
      const double y = table.number(row, columns[2]);
      pixel = Eigen::Vector2d(x, y);
      if (!pixel.allFinite()) {
        throw InputError(path, table.line(row),
                         "a detected corner needs finite x and y, not '" + x_text + " " + y_text +
                             "'");
      }
    }
    image.pixels.push_back(pixel);
    image.detected.push_back(detected);
    image.lines.push_back(table.line(row));
  }
  // `filename - - -` alone: the image has no board at all.
  for (ImageCorners& image : images) {
    if (image.pixels.size() == 1 && !image.detected[0]) {
      image.pixels.clear();
      image.detected.clear();
      image.lines.clear();
    }
  }
  return images;
}

std::vector<Eigen::Vector3d> read_board(const std::string& path) {
  const VnlogTable table = VnlogTable::read(path);
  const auto columns = table.columns({"index", "x", "y", "z"});
  std::vector<Eigen::Vector3d> points;
  for (std::size_t row = 0; row < table.num_rows(); ++row) {
    const double index = table.number(row, columns[0]);
    if (index != static_cast<double>(points.size())) {
      throw InputError(path, table.line(row),
                       "column 'index': expected " + std::to_string(points.size()) + ", found '" +
                           table.text(row, columns[0]) + "' (indices run 0, 1, 2, ...)");
    }
    Eigen::Vector3d point;
    for (int k = 0; k < 3; ++k) {
      point[k] = table.number(row, columns[k + 1]);
      if (!std::isfinite(point[k])) {
        throw InputError(path, table.line(row),
                         "column '" + table.column_names()[columns[k + 1]] + "': '" +
                             table.text(row, columns[k + 1]) + "' is not a finite number");
      }
    }
    points.push_back(point);
  }
  if (points.size() < 4) {
    throw InputError(path, 0, "a board needs at least 4 points, found " +
                                  std::to_string(points.size()));
  }
  // A board spans a plane: points on one line (or one point) place no view, and the corners
  // would be blamed for it.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) mean += p / static_cast<double>(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::Vector3d spread =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();  // ascending
  if (!(spread[1] > 1e-12 * spread[2]) || !(spread[2] > 0))
    throw InputError(path, 0,
                     "the board's points lie on one line or at one point: a board spans "
                     "a plane");
  return points;
}

std::vector<Eigen::Vector3d> regular_board(double spacing, int width_n, int height_n) {
  if (!(spacing > 0) || !std::isfinite(spacing) || width_n < 2 || height_n < 2) {
    throw std::invalid_argument(
        "a board needs a positive spacing and at least 2 points across and down");
  }
  std::vector<Eigen::Vector3d> points;
  for (int iy = 0; iy < height_n; ++iy) {
    for (int ix = 0; ix < width_n; ++ix) points.emplace_back(ix * spacing, iy * spacing, 0);
  }
  return points;
}

}  // namespace omnisfm::io
