#include "omnisfm/io/camera_covariance.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::io {
namespace {

std::string row_key(int i) { return "row_" + std::to_string(i); }

}  // namespace

IniSection covariance_section(const ParameterCovariance& covariance) {
  const auto n = static_cast<Eigen::Index>(covariance.parameters.size());
  if (covariance.matrix.rows() != n || covariance.matrix.cols() != n) {
    throw std::invalid_argument("covariance: expected a " + std::to_string(n) + "x" +
                                std::to_string(n) + " matrix");
  }
  IniSection section("<memory>", kCovarianceSection, 0);
  std::string names;
  for (const std::string& name : covariance.parameters) names += (names.empty() ? "" : " ") + name;
  section.set("parameters", names);
  for (Eigen::Index i = 0; i < n; ++i) {
    std::string row;
    for (Eigen::Index j = 0; j < n; ++j) {
      row += (j ? " " : "") + format_double(covariance.matrix(i, j));
    }
    section.set(row_key(static_cast<int>(i)), row);
  }
  return section;
}

std::optional<ParameterCovariance> covariance_from_ini(const IniFile& ini,
                                                       const camera::CatadioptricCamera& camera) {
  if (!ini.has_section(kCovarianceSection)) return std::nullopt;
  const IniSection& section = ini.section(kCovarianceSection);
  ParameterCovariance covariance;
  {
    std::istringstream names(section.get_string("parameters"));
    std::string name;
    const std::vector<std::string> known = camera.param_names();
    std::set<std::string> seen;
    while (names >> name) {
      if (std::find(known.begin(), known.end(), name) == known.end()) {
        section.fail("parameters", "the camera has no parameter '" + name + "'");
      }
      if (!seen.insert(name).second) section.fail("parameters", "'" + name + "' is listed twice");
      covariance.parameters.push_back(name);
    }
  }
  const int n = static_cast<int>(covariance.parameters.size());
  if (n == 0) section.fail("parameters", "no parameter names");
  covariance.matrix.resize(n, n);
  for (int i = 0; i < n; ++i) {
    const std::vector<double> row = section.get_doubles(row_key(i));
    if (static_cast<int>(row.size()) != n) {
      section.fail(row_key(i), "expected " + std::to_string(n) + " numbers, found " +
                                   std::to_string(row.size()));
    }
    for (int j = 0; j < n; ++j) {
      if (!std::isfinite(row[j])) section.fail(row_key(i), "must be finite numbers");
      covariance.matrix(i, j) = row[j];
    }
    if (row[i] < 0) section.fail(row_key(i), "a variance cannot be negative");
  }
  for (const IniEntry& entry : section.unread()) section.fail(entry.key, "unknown key");
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < i; ++j) {
      const double a = covariance.matrix(i, j), b = covariance.matrix(j, i);
      if (std::abs(a - b) > 1e-9 * std::max({std::abs(a), std::abs(b), 1e-300})) {
        section.fail(row_key(i), "the matrix is not symmetric: entry " + std::to_string(j) +
                                     " differs from " + row_key(j) + "'s entry " +
                                     std::to_string(i));
      }
    }
  }
  return covariance;
}

std::optional<ParameterCovariance> read_camera_covariance(const std::string& path) {
  const IniFile ini = IniFile::read(path);
  return covariance_from_ini(ini, camera_from_ini(ini));
}

void write_calibrated_camera_file(const std::string& path, const camera::CatadioptricCamera& camera,
                                  const ParameterCovariance& covariance) {
  write_camera_file(path, camera, {covariance_section(covariance)});
}

}  // namespace omnisfm::io
