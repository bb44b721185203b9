#include "omnisfm/io/camera_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "omnisfm/camera/camera_kinds.h"
#include "omnisfm/camera/mrcal_camera.h"
#include "omnisfm/camera/table_profile.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {

namespace fs = std::filesystem;
using camera::CatadioptricCamera;
using camera::InnerCamera;
using camera::InnerKind;
using camera::MirrorKind;
using camera::MirrorProfile;

namespace {

constexpr double kPi = 3.14159265358979323846;

const std::vector<std::string> kCommonKeys = {"image_width", "image_height", "inner",
                                              "mirror",      "mirror_rx",    "mirror_ry",
                                              "mirror_tx",   "mirror_ty",    "mirror_tz"};

std::vector<std::string> inner_keys(InnerKind kind) {
  switch (kind) {
    case InnerKind::kPinhole:
      return {"fx", "fy", "cx", "cy", "dist"};
    case InnerKind::kOrthographic:
      return {"fx", "fy", "cx", "cy"};
    case InnerKind::kMrcal:
      return {"inner_cameramodel"};
  }
  return {};
}

std::vector<std::string> mirror_keys(MirrorKind kind) {
  switch (kind) {
    case MirrorKind::kEquiangular:
      return {"equiangular_alpha", "equiangular_r0", "mirror_theta_min", "mirror_theta_max"};
    case MirrorKind::kConic:
      return {"conic_z0", "conic_c", "conic_kappa", "mirror_rho_min", "mirror_rho_max"};
    case MirrorKind::kTable:
      return {"mirror_table", "mirror_rho_min", "mirror_rho_max"};
  }
  return {};
}

bool contains(const std::vector<std::string>& list, const std::string& item) {
  return std::find(list.begin(), list.end(), item) != list.end();
}

std::string joined(const std::vector<std::string>& list, const std::string& separator) {
  std::string text;
  for (const std::string& item : list) text += (text.empty() ? "" : separator) + item;
  return text;
}

template <typename Kind>
Kind kind_of(const IniSection& section, const std::string& key, const std::vector<Kind>& kinds,
             bool (*named)(const std::string&, Kind*)) {
  const std::string name = section.get_string(key);
  Kind kind;
  if (!named(name, &kind)) {
    std::vector<std::string> names;
    for (Kind k : kinds) names.push_back(camera::name_of(k));
    section.fail(key, "'" + name + "' is not one of " + joined(names, ", "));
  }
  return kind;
}

// Reports the first key, in file order, that the chosen inner camera and mirror do not use.
void reject_unknown_keys(const IniSection& section, InnerKind inner_kind, MirrorKind mirror_kind) {
  std::vector<std::string> allowed = kCommonKeys;
  for (const std::string& key : inner_keys(inner_kind)) allowed.push_back(key);
  for (const std::string& key : mirror_keys(mirror_kind)) allowed.push_back(key);
  for (const IniEntry& entry : section.entries()) {
    if (contains(allowed, entry.key)) continue;
    bool for_inner = false, for_mirror = false;
    for (InnerKind kind : camera::inner_kinds()) for_inner |= contains(inner_keys(kind), entry.key);
    for (MirrorKind kind : camera::mirror_kinds())
      for_mirror |= contains(mirror_keys(kind), entry.key);
    if (for_inner)
      section.fail(entry.key, std::string("does not apply to inner = ") + name_of(inner_kind));
    if (for_mirror)
      section.fail(entry.key, std::string("does not apply to mirror = ") + name_of(mirror_kind));
    section.fail(entry.key, "unknown key");
  }
}

// A key under an unknown header, or before any, would silently leave [omni_camera] and its
// optional keys fall back to their defaults: a camera file holds only its own sections.
void reject_unknown_sections(const IniFile& ini) {
  for (const IniSection& section : ini.sections()) {
    if (section.name() == kCameraSection || section.name() == kCovarianceSection) continue;
    if (section.name().empty()) {
      if (section.entries().empty()) continue;
      section.fail(section.entries().front().key,
                   std::string("belongs in the [") + kCameraSection + "] section");
    }
    throw InputError(ini.file(), section.line(),
                     "unknown section [" + section.name() + "]: a camera file holds [" +
                         kCameraSection + "] and, after a calibration, [" + kCovarianceSection +
                         "]");
  }
}

double finite(const IniSection& section, const std::string& key) {
  const double value = section.get_double(key);
  if (!std::isfinite(value)) section.fail(key, "must be a finite number");
  return value;
}

double finite_or(const IniSection& section, const std::string& key, double fallback) {
  return section.has(key) ? finite(section, key) : fallback;
}

double positive(const IniSection& section, const std::string& key) {
  const double value = finite(section, key);
  if (!(value > 0)) section.fail(key, "must be positive, not " + format_double(value));
  return value;
}

int positive_int(const IniSection& section, const std::string& key) {
  const int value = section.get_int(key);
  if (value <= 0) section.fail(key, "must be positive, not " + std::to_string(value));
  return value;
}

// A path in the file, taken relative to the file's folder.
std::string referenced_path(const IniSection& section, const std::string& key) {
  const std::string value = section.get_string(key);
  if (value.empty()) section.fail(key, "no file given");
  const fs::path path(value);
  if (path.is_absolute()) return path.string();
  return (fs::path(section.file()).parent_path() / path).string();
}

std::unique_ptr<InnerCamera> read_inner(const IniSection& section, InnerKind kind, int width,
                                        int height) {
  if (kind == InnerKind::kMrcal) {
    const std::string path = referenced_path(section, "inner_cameramodel");
    std::unique_ptr<camera::MrcalCamera> inner;
    try {
      inner = std::make_unique<camera::MrcalCamera>(camera::MrcalCamera::from_file(path));
    } catch (const std::exception& error) {
      section.fail("inner_cameramodel", std::string("cannot read the mrcal model: ") + error.what());
    }
    if (inner->image_width() != width || inner->image_height() != height) {
      section.fail("inner_cameramodel",
                   "its imagersize " + std::to_string(inner->image_width()) + "x" +
                       std::to_string(inner->image_height()) + " differs from image_width x " +
                       "image_height = " + std::to_string(width) + "x" + std::to_string(height));
    }
    return inner;
  }
  const double fx = positive(section, "fx");
  const double fy = positive(section, "fy");
  // Pixels are near square in every camera; a factor beyond 10 is a slip (1e308 for 800 left a
  // camera that sees one line of the world).
  constexpr double kMaxAspect = 10;
  if (!(fx <= kMaxAspect * fy && fy <= kMaxAspect * fx))
    section.fail("fy", "must be within a factor " + format_double(kMaxAspect) +
                           " of fx = " + format_double(fx) + ", not " + format_double(fy));
  const double cx = finite(section, "cx");
  const double cy = finite(section, "cy");
  try {
    if (kind == InnerKind::kOrthographic)
      return camera::make_inner(kind, Eigen::Vector4d(fx, fy, cx, cy));
    const std::vector<double> dist = section.get_doubles("dist", {0, 0, 0, 0, 0});
    if (dist.size() != 5) {
      section.fail("dist", "expected 5 numbers (k1 k2 p1 p2 k3), found " +
                               std::to_string(dist.size()));
    }
    for (double coefficient : dist) {
      if (!std::isfinite(coefficient)) section.fail("dist", "must be finite numbers");
    }
    Eigen::VectorXd params(9);
    params << fx, fy, cx, cy, dist[0], dist[1], dist[2], dist[3], dist[4];
    return camera::make_inner(kind, params);
  } catch (const std::invalid_argument& error) {
    section.fail("inner", error.what());
  }
}

// Checks 0 <= min < max, blaming the key whose value is out of place.
void check_range(const IniSection& section, const std::string& min_key, double min,
                 const std::string& max_key, double max) {
  if (min < 0) section.fail(min_key, "must not be negative, not " + format_double(min));
  if (!(max > min)) {
    section.fail(max_key, "must be greater than " + min_key + " = " + format_double(min) +
                              ", not " + format_double(max));
  }
}

std::unique_ptr<MirrorProfile> read_equiangular(const IniSection& section) {
  const double alpha = positive(section, "equiangular_alpha");
  const double r0 = positive(section, "equiangular_r0");
  const double theta_min = finite(section, "mirror_theta_min");
  const double theta_max = finite(section, "mirror_theta_max");
  check_range(section, "mirror_theta_min", theta_min, "mirror_theta_max", theta_max);
  const double theta_limit = kPi / (1 + alpha);
  if (!(theta_max < theta_limit)) {
    section.fail("mirror_theta_max", "must be below pi/(1 + equiangular_alpha) = " +
                                         format_double(theta_limit) + ", not " +
                                         format_double(theta_max));
  }
  return camera::make_mirror(MirrorKind::kEquiangular, Eigen::Vector2d(alpha, r0), theta_min,
                             theta_max);
}

std::unique_ptr<MirrorProfile> read_conic(const IniSection& section) {
  const double z0 = finite(section, "conic_z0");
  const double c = positive(section, "conic_c");
  const double kappa = finite(section, "conic_kappa");
  const double rho_min = finite(section, "mirror_rho_min");
  const double rho_max = finite(section, "mirror_rho_max");
  check_range(section, "mirror_rho_min", rho_min, "mirror_rho_max", rho_max);
  // The sag formula needs (1 + kappa) c^2 rho^2 < 1.
  if ((1 + kappa) * c * c * rho_max * rho_max >= 1) {
    section.fail("mirror_rho_max", "must be below the conic's edge 1/(c sqrt(1 + kappa)) = " +
                                       format_double(1 / (c * std::sqrt(1 + kappa))) + ", not " +
                                       format_double(rho_max));
  }
  return camera::make_mirror(MirrorKind::kConic, Eigen::Vector3d(z0, c, kappa), rho_min, rho_max);
}

std::unique_ptr<MirrorProfile> read_table(const IniSection& section) {
  const std::string path = referenced_path(section, "mirror_table");
  std::vector<double> rho, z;
  try {
    const VnlogTable table = VnlogTable::read(path);
    rho = table.numbers("rho");
    z = table.numbers("z");
    for (std::size_t row = 0; row < table.num_rows(); ++row) {
      if (!std::isfinite(rho[row]) || !std::isfinite(z[row])) {
        throw InputError(path, table.line(row), "rho and z must be finite numbers");
      }
      if (row > 0 && !(rho[row] > rho[row - 1])) {
        throw InputError(path, table.line(row), "rho must increase from row to row");
      }
    }
    if (table.num_rows() < 4) {
      throw InputError(path, 0,
                       "needs at least 4 rows, has " + std::to_string(table.num_rows()));
    }
  } catch (const InputError& error) {
    section.fail("mirror_table", error.what());
  }
  const double rho_min = finite(section, "mirror_rho_min");
  const double rho_max = finite(section, "mirror_rho_max");
  check_range(section, "mirror_rho_min", rho_min, "mirror_rho_max", rho_max);
  if (rho_min < rho.front()) {
    section.fail("mirror_rho_min", "must lie inside the table, which starts at rho = " +
                                       format_double(rho.front()));
  }
  if (rho_max > rho.back()) {
    section.fail("mirror_rho_max", "must lie inside the table, which ends at rho = " +
                                       format_double(rho.back()));
  }
  return camera::make_mirror(MirrorKind::kTable, Eigen::VectorXd(0), rho_min, rho_max,
                             {std::move(rho), std::move(z)});
}

std::unique_ptr<MirrorProfile> read_mirror(const IniSection& section, MirrorKind kind) {
  try {
    switch (kind) {
      case MirrorKind::kEquiangular:
        return read_equiangular(section);
      case MirrorKind::kConic:
        return read_conic(section);
      case MirrorKind::kTable:
        return read_table(section);
    }
    section.fail("mirror", "unknown kind");
  } catch (const std::invalid_argument& error) {
    section.fail("mirror", error.what());
  }
}

}  // namespace

namespace {

// A mirror angle, radians: finite, and within +-pi (beyond it the same pose is meant another way,
// or a unit was mistaken).
double angle_or(const IniSection& section, const std::string& key, double fallback) {
  const double value = finite_or(section, key, fallback);
  if (std::abs(value) > M_PI)
    section.fail(key, "must be an angle within -pi and pi (radians), not " + format_double(value));
  return value;
}

// Whether the image sees the world through the mirror: some pixels of a coarse grid over it
// unproject, and their rays span more than a degree. A camera that passes every parameter's own
// check can still see nothing, or one direction only (a mirror 1e10 m away, a focal length of
// 1e308), and the estimators then fail far from the file's line.
bool sees_through_its_mirror(const CatadioptricCamera& camera) {
  constexpr int kColumns = 64, kRows = 48;
  const double min_cos = std::cos(M_PI / 180);
  std::optional<Eigen::Vector3d> first;
  Eigen::Vector3d origin, direction;
  for (int j = 0; j < kRows; ++j)
    for (int i = 0; i < kColumns; ++i) {
      const Eigen::Vector2d pixel((i + 0.5) * camera.image_width() / kColumns - 0.5,
                                  (j + 0.5) * camera.image_height() / kRows - 0.5);
      if (!camera.unproject(pixel, &origin, &direction) || !origin.allFinite() ||
          !direction.allFinite() || !(direction.norm() > 0))
        continue;
      if (!first)
        first = direction.normalized();
      else if (first->dot(direction.normalized()) < min_cos)
        return true;
    }
  return false;
}

}  // namespace

CatadioptricCamera camera_from_ini(const IniFile& ini) {
  reject_unknown_sections(ini);
  const IniSection& section = ini.section(kCameraSection);
  const InnerKind inner_kind =
      kind_of(section, "inner", camera::inner_kinds(), &camera::inner_kind_named);
  const MirrorKind mirror_kind =
      kind_of(section, "mirror", camera::mirror_kinds(), &camera::mirror_kind_named);
  reject_unknown_keys(section, inner_kind, mirror_kind);

  const int width = positive_int(section, "image_width");
  const int height = positive_int(section, "image_height");
  std::unique_ptr<InnerCamera> inner = read_inner(section, inner_kind, width, height);
  std::unique_ptr<MirrorProfile> mirror = read_mirror(section, mirror_kind);
  camera::MirrorPose pose;
  pose.rx = angle_or(section, "mirror_rx", 0);
  pose.ry = angle_or(section, "mirror_ry", 0);
  pose.tx = finite_or(section, "mirror_tx", 0);
  pose.ty = finite_or(section, "mirror_ty", 0);
  pose.tz = finite_or(section, "mirror_tz", 0);
  std::optional<CatadioptricCamera> camera;
  try {
    camera.emplace(std::move(inner), std::move(mirror), pose, width, height);
  } catch (const std::invalid_argument& error) {
    throw InputError(ini.file(), section.line(), error.what());
  }
  if (!sees_through_its_mirror(*camera))
    throw InputError(ini.file(), section.line(),
                     "the " + std::to_string(width) + "x" + std::to_string(height) +
                         " image sees less than a degree of the world through the mirror: the "
                         "parameters place the mirror's picture off the image, or shrink it to a "
                         "point");
  return std::move(*camera);
}

CatadioptricCamera read_camera_file(const std::string& path) {
  return camera_from_ini(IniFile::read(path));
}

namespace {

void set_number(IniSection& section, const std::string& key, double value) {
  section.set(key, format_double(value));
}

void write_inner(const InnerCamera& inner, const fs::path& ini_path, IniSection& section) {
  section.set("inner", camera::name_of(inner.kind()));
  const Eigen::VectorXd p = inner.params();
  switch (inner.kind()) {
    case InnerKind::kPinhole:
    case InnerKind::kOrthographic:
      set_number(section, "fx", p[0]);
      set_number(section, "fy", p[1]);
      set_number(section, "cx", p[2]);
      set_number(section, "cy", p[3]);
      if (inner.kind() == InnerKind::kPinhole)
        section.set("dist", format_double(p[4]) + " " + format_double(p[5]) + " " +
                                format_double(p[6]) + " " + format_double(p[7]) + " " +
                                format_double(p[8]));
      return;
    case InnerKind::kMrcal: {
      const auto& mrcal = static_cast<const camera::MrcalCamera&>(inner);
      const std::string name = ini_path.stem().string() + ".inner.cameramodel";
      write_atomically((ini_path.parent_path() / name).string(),
                       [&mrcal](const std::string& temporary) { mrcal.write(temporary); });
      section.set("inner_cameramodel", name);
      return;
    }
  }
}

void write_mirror(const MirrorProfile& mirror, const fs::path& ini_path, IniSection& section) {
  section.set("mirror", camera::name_of(mirror.kind()));
  const Eigen::VectorXd shape = mirror.shape_params();
  switch (mirror.kind()) {
    case MirrorKind::kEquiangular:
      set_number(section, "equiangular_alpha", shape[0]);
      set_number(section, "equiangular_r0", shape[1]);
      set_number(section, "mirror_theta_min", mirror.s_min());
      set_number(section, "mirror_theta_max", mirror.s_max());
      return;
    case MirrorKind::kConic:
      set_number(section, "conic_z0", shape[0]);
      set_number(section, "conic_c", shape[1]);
      set_number(section, "conic_kappa", shape[2]);
      break;
    case MirrorKind::kTable: {
      const auto& table = static_cast<const camera::TableProfile&>(mirror);
      const std::string name = ini_path.stem().string() + ".profile.vnl";
      write_text_atomically((ini_path.parent_path() / name).string(), [&table](std::ostream& out) {
        VnlogWriter writer(out, {"rho", "z"});
        for (std::size_t i = 0; i < table.rho_samples().size(); ++i) {
          writer.row({table.rho_samples()[i], table.z_samples()[i]});
        }
      });
      section.set("mirror_table", name);
      break;
    }
  }
  set_number(section, "mirror_rho_min", mirror.s_min());
  set_number(section, "mirror_rho_max", mirror.s_max());
}

}  // namespace

void write_camera_file(const std::string& path, const CatadioptricCamera& camera) {
  write_camera_file(path, camera, {});
}

void write_camera_file(const std::string& path, const CatadioptricCamera& camera,
                       const std::vector<IniSection>& more_sections) {
  IniFile ini(path);
  IniSection& section = ini.add_section(kCameraSection);
  section.set("image_width", std::to_string(camera.image_width()));
  section.set("image_height", std::to_string(camera.image_height()));
  write_inner(camera.inner(), fs::path(path), section);
  write_mirror(camera.mirror(), fs::path(path), section);
  const camera::MirrorPose& pose = camera.mirror_pose();
  set_number(section, "mirror_rx", pose.rx);
  set_number(section, "mirror_ry", pose.ry);
  set_number(section, "mirror_tx", pose.tx);
  set_number(section, "mirror_ty", pose.ty);
  set_number(section, "mirror_tz", pose.tz);
  for (const IniSection& more : more_sections) {
    if (more.name() == kCameraSection || more.name().empty()) {
      throw std::invalid_argument("write_camera_file: a further section must have its own name");
    }
    IniSection& copy = ini.add_section(more.name());
    for (const IniEntry& entry : more.entries()) copy.set(entry.key, entry.value);
  }
  write_text_atomically(path, [&ini](std::ostream& out) { ini.write(out); });
}

}  // namespace omnisfm::io
