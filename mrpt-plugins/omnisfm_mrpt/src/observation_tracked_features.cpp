#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <ostream>

#include "omnisfm/io/number_text.h"

IMPLEMENTS_SERIALIZABLE(CObservationTrackedFeatures, mrpt::obs::CObservation, omnisfm::mrpt_plugin)

namespace omnisfm::mrpt_plugin {

uint8_t CObservationTrackedFeatures::serializeGetVersion() const { return 0; }

void CObservationTrackedFeatures::serializeTo(mrpt::serialization::CArchive& out) const {
  out << timestamp << sensorLabel;
  out.WriteAs<int32_t>(frame);
  out << sensorPose << model;
  out.WriteAs<uint32_t>(static_cast<uint32_t>(features.size()));
  for (const TrackedFeature& f : features) {
    out.WriteAs<int32_t>(f.track);
    out << f.u << f.v;
  }
}

void CObservationTrackedFeatures::serializeFrom(mrpt::serialization::CArchive& in,
                                                uint8_t version) {
  switch (version) {
    case 0: {
      in >> timestamp >> sensorLabel;
      frame = in.ReadAs<int32_t>();
      in >> sensorPose >> model;
      const uint32_t count = in.ReadAs<uint32_t>();
      features.clear();
      // A corrupt count must not allocate gigabytes before the stream runs out.
      features.reserve(std::min<uint32_t>(count, 1u << 16));
      for (uint32_t i = 0; i < count; ++i) {
        TrackedFeature f;
        f.track = in.ReadAs<int32_t>();
        in >> f.u >> f.v;
        features.push_back(f);
      }
      break;
    }
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

void CObservationTrackedFeatures::getDescriptionAsText(std::ostream& o) const {
  CObservation::getDescriptionAsText(o);
  o << "Tracked features (omnisfm): frame " << frame << ", " << features.size() << " features\n";
  o << "Camera pose on the robot: " << sensorPose << "\n";
  model.getDescriptionAsText(o);
  o << "# track u v\n";
  for (const TrackedFeature& f : features)
    o << f.track << " " << io::format_double(f.u) << " " << io::format_double(f.v) << "\n";
}

}  // namespace omnisfm::mrpt_plugin

namespace omnisfm::mrpt_plugin {

std::string CObservationTrackedFeatures::exportTxtHeader() const {
  return "FRAME FEATURE_COUNT then, per feature: TRACK U V";
}

std::string CObservationTrackedFeatures::exportTxtDataRow() const {
  std::string row = std::to_string(frame) + " " + std::to_string(features.size());
  for (const TrackedFeature& f : features)
    row += " " + std::to_string(f.track) + " " + io::format_double(f.u) + " " +
           io::format_double(f.v);
  return row;
}

void CObservationTrackedFeatures::getVisualizationInto(mrpt::opengl::CSetOfObjects& o) const {
  if (!model.has_camera()) return;
  auto rays = mrpt::opengl::CSetOfLines::Create();
  rays->setName("omnisfm rays, frame " + std::to_string(frame));
  for (const TrackedFeature& f : features) {
    Eigen::Vector3d origin, direction;
    if (!model.camera().unproject({f.u, f.v}, &origin, &direction)) continue;
    const Eigen::Vector3d end = origin + kVisualizedRayLength * direction.normalized();
    const mrpt::math::TPoint3D from = sensorPose.composePoint({origin.x(), origin.y(), origin.z()});
    const mrpt::math::TPoint3D to = sensorPose.composePoint({end.x(), end.y(), end.z()});
    rays->appendLine(from.x, from.y, from.z, to.x, to.y, to.z);
  }
  o.insert(rays);
}

}  // namespace omnisfm::mrpt_plugin
