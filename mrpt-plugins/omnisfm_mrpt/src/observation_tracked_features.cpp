#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

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
