#pragma once
// The camera file: section [omni_camera] of an INI file (DESIGN.md section 3).
//   image_width, image_height         pixels, > 0
//   inner = pinhole | orthographic | mrcal
//     pinhole:       fx fy cx cy, dist = k1 k2 p1 p2 k3 (optional, zeros by default)
//     orthographic:  fx fy cx cy (pixels per metre)
//     mrcal:         inner_cameramodel = a .cameramodel path, relative to the file's folder
//   mirror = equiangular | conic | table
//     equiangular:   equiangular_alpha, equiangular_r0, mirror_theta_min, mirror_theta_max
//     conic:         conic_z0, conic_c, conic_kappa, mirror_rho_min, mirror_rho_max
//     table:         mirror_table = a `# rho z` vnlog path (relative to the file's folder),
//                    mirror_rho_min, mirror_rho_max
//   mirror_rx mirror_ry mirror_tx mirror_ty mirror_tz   optional, 0 by default
// The only other section is a calibration's [omni_camera_covariance], left to its own reader;
// any other section, or a key before the first section, is an error.

#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/ini_file.h"

namespace omnisfm::io {

inline constexpr const char* kCameraSection = "omni_camera";

// Throws InputError naming the file, the key and its line for a missing, unknown (including one
// that belongs to another inner camera or mirror kind), non-numeric or out-of-range value, and
// for a referenced file that cannot be read; and naming the file and line of an unknown section.
camera::CatadioptricCamera read_camera_file(const std::string& path);
// The same from an INI file already read; relative paths are taken from the folder of ini.file().
camera::CatadioptricCamera camera_from_ini(const IniFile& ini);

// Writes every key with round-trip precision. A table mirror's samples go to
// <stem>.profile.vnl and an mrcal inner camera to <stem>.inner.cameramodel, beside the file and
// referenced by name. Each file is replaced whole or not at all; throws std::runtime_error when
// writing fails.
void write_camera_file(const std::string& path, const camera::CatadioptricCamera& camera);
// The same with further sections after [omni_camera] (a calibration's covariance), written in
// the same atomic replacement.
void write_camera_file(const std::string& path, const camera::CatadioptricCamera& camera,
                       const std::vector<IniSection>& more_sections);

}  // namespace omnisfm::io
