#pragma once
// A calibration's parameter covariance, the second section of a calibrated camera file:
//   [omni_camera_covariance]
//   parameters = mirror_rx mirror_ry mirror_tx mirror_ty mirror_tz   # CatadioptricCamera names
//   row_0 = 1.2e-08 ...                                              # one row per parameter
//   ...
// in the parameters' own units (pixels, metres, radians), symmetric. Parameters not listed were
// held fixed by the calibration.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/ini_file.h"

namespace omnisfm::io {

inline constexpr const char* kCovarianceSection = "omni_camera_covariance";

struct ParameterCovariance {
  std::vector<std::string> parameters;
  Eigen::MatrixXd matrix;
};

// The section for `covariance`, every number with round-trip precision. Throws
// std::invalid_argument when the matrix is not square with one row per name.
IniSection covariance_section(const ParameterCovariance& covariance);

// The covariance in a camera file, or nothing when it has no such section. Throws InputError
// naming the file, the key and its line for: a missing `parameters` or row key, an unknown key, a
// name the file's camera does not have or that is listed twice, a row with the wrong count or a
// non-number, an asymmetric matrix or a negative variance.
std::optional<ParameterCovariance> read_camera_covariance(const std::string& path);
std::optional<ParameterCovariance> covariance_from_ini(const IniFile& ini,
                                                       const camera::CatadioptricCamera& camera);

// Writes the camera file (as write_camera_file) with the covariance section after it.
void write_calibrated_camera_file(const std::string& path, const camera::CatadioptricCamera& camera,
                                  const ParameterCovariance& covariance);

}  // namespace omnisfm::io
