#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"

#include <mrpt/serialization/CArchive.h>

#include <ostream>
#include <stdexcept>
#include <string>

#include "omnisfm/camera/camera_kinds.h"
#include "omnisfm/camera/mrcal_camera.h"
#include "omnisfm/camera/table_profile.h"
#include "omnisfm/io/number_text.h"

IMPLEMENTS_SERIALIZABLE(CCatadioptricCameraModel, mrpt::serialization::CSerializable,
                        omnisfm::mrpt_plugin)

namespace omnisfm::mrpt_plugin {
namespace {

using mrpt::serialization::CArchive;

std::vector<double> to_std(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

Eigen::VectorXd to_eigen(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error("CCatadioptricCameraModel: the stored model is not a valid camera: " +
                           what);
}

std::unique_ptr<camera::InnerCamera> read_inner(CArchive& in) {
  std::string name;
  std::vector<double> p;
  in >> name >> p;
  camera::InnerKind kind;
  if (!camera::inner_kind_named(name, &kind)) fail("unknown inner camera kind '" + name + "'");
  camera::MrcalLens lens;
  if (kind == camera::InnerKind::kMrcal) {
    in >> lens.lensmodel;
    lens.image_width = in.ReadAs<int32_t>();
    lens.image_height = in.ReadAs<int32_t>();
  }
  return camera::make_inner(kind, to_eigen(p), lens);
}

void write_inner(CArchive& out, const camera::InnerCamera& inner) {
  out << std::string(camera::name_of(inner.kind())) << to_std(inner.params());
  if (inner.kind() == camera::InnerKind::kMrcal) {
    const auto& mrcal = static_cast<const camera::MrcalCamera&>(inner);
    out << mrcal.lensmodel_name();
    out.WriteAs<int32_t>(mrcal.image_width());
    out.WriteAs<int32_t>(mrcal.image_height());
  }
}

std::unique_ptr<camera::MirrorProfile> read_mirror(CArchive& in) {
  std::string name;
  std::vector<double> shape;
  double s_min = 0, s_max = 0;
  in >> name >> shape >> s_min >> s_max;
  camera::MirrorKind kind;
  if (!camera::mirror_kind_named(name, &kind)) fail("unknown mirror kind '" + name + "'");
  camera::ProfileTable table;
  if (kind == camera::MirrorKind::kTable) in >> table.rho >> table.z;
  return camera::make_mirror(kind, to_eigen(shape), s_min, s_max, table);
}

void write_mirror(CArchive& out, const camera::MirrorProfile& mirror) {
  out << std::string(camera::name_of(mirror.kind())) << to_std(mirror.shape_params())
      << mirror.s_min() << mirror.s_max();
  if (mirror.kind() == camera::MirrorKind::kTable) {
    const auto& table = static_cast<const camera::TableProfile&>(mirror);
    out << table.rho_samples() << table.z_samples();
  }
}

camera::CatadioptricCamera read_camera_v0(CArchive& in) {
  const int32_t width = in.ReadAs<int32_t>();
  const int32_t height = in.ReadAs<int32_t>();
  try {
    std::unique_ptr<camera::InnerCamera> inner = read_inner(in);
    std::unique_ptr<camera::MirrorProfile> mirror = read_mirror(in);
    camera::MirrorPose pose;
    in >> pose.rx >> pose.ry >> pose.tx >> pose.ty >> pose.tz;
    return camera::CatadioptricCamera(std::move(inner), std::move(mirror), pose, width, height);
  } catch (const std::invalid_argument& error) {
    fail(error.what());
  }
}

}  // namespace

CCatadioptricCameraModel::CCatadioptricCameraModel(camera::CatadioptricCamera camera)
    : camera_(std::move(camera)) {}

const camera::CatadioptricCamera& CCatadioptricCameraModel::camera() const {
  if (!camera_) throw std::logic_error("CCatadioptricCameraModel: no camera in this model");
  return *camera_;
}

uint8_t CCatadioptricCameraModel::serializeGetVersion() const { return 0; }

void CCatadioptricCameraModel::serializeTo(mrpt::serialization::CArchive& out) const {
  out << camera_.has_value();
  if (!camera_) return;
  out.WriteAs<int32_t>(camera_->image_width());
  out.WriteAs<int32_t>(camera_->image_height());
  write_inner(out, camera_->inner());
  write_mirror(out, camera_->mirror());
  const camera::MirrorPose& pose = camera_->mirror_pose();
  out << pose.rx << pose.ry << pose.tx << pose.ty << pose.tz;
}

void CCatadioptricCameraModel::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version) {
  switch (version) {
    case 0: {
      // Stored as a bool's one byte, read as a byte: a damaged one that is neither 0 nor 1 read
      // into a bool would be undefined behaviour.
      const auto has_camera = in.ReadAs<uint8_t>();
      if (has_camera > 1) fail("its camera flag is " + std::to_string(has_camera) + ", not 0 or 1");
      camera_.reset();
      if (has_camera == 1) camera_ = read_camera_v0(in);
      break;
    }
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

void CCatadioptricCameraModel::getDescriptionAsText(std::ostream& o) const {
  if (!camera_) {
    o << "Catadioptric camera model: none\n";
    return;
  }
  const camera::CatadioptricCamera& c = *camera_;
  o << "Catadioptric camera model: " << camera::name_of(c.inner().kind()) << " camera, "
    << camera::name_of(c.mirror().kind())
    << " mirror, " << c.image_width() << "x" << c.image_height() << " pixels\n";
  if (const auto* mrcal = dynamic_cast<const camera::MrcalCamera*>(&c.inner()))
    o << "  lens model: " << mrcal->lensmodel_name() << "\n";
  const std::vector<std::string> names = c.param_names();
  const Eigen::VectorXd values = c.params();
  for (size_t i = 0; i < names.size(); ++i)
    o << "  " << names[i] << " = " << io::format_double(values[static_cast<Eigen::Index>(i)])
      << "\n";
  o << "  mirror valid range: " << io::format_double(c.mirror().s_min()) << " .. "
    << io::format_double(c.mirror().s_max()) << "\n";
  if (const auto* table = dynamic_cast<const camera::TableProfile*>(&c.mirror()))
    o << "  mirror table: " << table->rho_samples().size() << " samples\n";
}

}  // namespace omnisfm::mrpt_plugin
