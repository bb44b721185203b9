#include "omnisfm/camera/camera_kinds.h"

#include <stdexcept>

#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/mrcal_camera.h"
#include "omnisfm/camera/orthographic_camera.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/camera/table_profile.h"

namespace omnisfm::camera {
namespace {

void require_size(const Eigen::VectorXd& v, Eigen::Index size, const std::string& what) {
  if (v.size() != size)
    throw std::invalid_argument(what + " takes " + std::to_string(size) + " parameters, not " +
                                std::to_string(v.size()));
}

}  // namespace

const char* name_of(InnerKind kind) {
  switch (kind) {
    case InnerKind::kPinhole:
      return "pinhole";
    case InnerKind::kOrthographic:
      return "orthographic";
    case InnerKind::kMrcal:
      return "mrcal";
  }
  return "?";
}

const char* name_of(MirrorKind kind) {
  switch (kind) {
    case MirrorKind::kEquiangular:
      return "equiangular";
    case MirrorKind::kConic:
      return "conic";
    case MirrorKind::kTable:
      return "table";
  }
  return "?";
}

const std::vector<InnerKind>& inner_kinds() {
  static const std::vector<InnerKind> kinds = {InnerKind::kPinhole, InnerKind::kOrthographic,
                                               InnerKind::kMrcal};
  return kinds;
}

const std::vector<MirrorKind>& mirror_kinds() {
  static const std::vector<MirrorKind> kinds = {MirrorKind::kEquiangular, MirrorKind::kConic,
                                                MirrorKind::kTable};
  return kinds;
}

namespace {

template <typename Kind>
bool kind_named(const std::string& name, const std::vector<Kind>& kinds, Kind* kind) {
  for (Kind k : kinds)
    if (name == name_of(k)) {
      *kind = k;
      return true;
    }
  return false;
}

}  // namespace

bool inner_kind_named(const std::string& name, InnerKind* kind) {
  return kind_named(name, inner_kinds(), kind);
}

bool mirror_kind_named(const std::string& name, MirrorKind* kind) {
  return kind_named(name, mirror_kinds(), kind);
}

std::unique_ptr<InnerCamera> make_inner(InnerKind kind, const Eigen::VectorXd& p,
                                        const MrcalLens& mrcal) {
  switch (kind) {
    case InnerKind::kPinhole:
      require_size(p, 9, "a pinhole camera");
      return std::make_unique<PinholeCamera>(
          PinholeIntrinsics{p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8]});
    case InnerKind::kOrthographic:
      require_size(p, 4, "an orthographic camera");
      return std::make_unique<OrthographicCamera>(OrthographicIntrinsics{p[0], p[1], p[2], p[3]});
    case InnerKind::kMrcal:
      return std::make_unique<MrcalCamera>(mrcal.lensmodel, p, mrcal.image_width,
                                           mrcal.image_height);
  }
  throw std::invalid_argument("unknown inner camera kind");
}

std::unique_ptr<MirrorProfile> make_mirror(MirrorKind kind, const Eigen::VectorXd& shape,
                                           double s_min, double s_max, const ProfileTable& table) {
  switch (kind) {
    case MirrorKind::kEquiangular:
      require_size(shape, 2, "an equiangular mirror");
      return std::make_unique<EquiangularProfile>(shape[0], shape[1], s_min, s_max);
    case MirrorKind::kConic:
      require_size(shape, 3, "a conic mirror");
      return std::make_unique<ConicProfile>(shape[0], shape[1], shape[2], s_min, s_max);
    case MirrorKind::kTable:
      require_size(shape, 0, "a tabulated mirror");
      return std::make_unique<TableProfile>(table.rho, table.z, s_min, s_max);
  }
  throw std::invalid_argument("unknown mirror kind");
}

}  // namespace omnisfm::camera
