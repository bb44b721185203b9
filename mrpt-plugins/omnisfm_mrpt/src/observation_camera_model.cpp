#include "omnisfm/mrpt_plugin/observation_camera_model.h"

#include <mrpt/serialization/CArchive.h>

#include <ostream>

IMPLEMENTS_SERIALIZABLE(CObservationCameraModel, mrpt::obs::CObservation, omnisfm::mrpt_plugin)

namespace omnisfm::mrpt_plugin {

uint8_t CObservationCameraModel::serializeGetVersion() const { return 0; }

void CObservationCameraModel::serializeTo(mrpt::serialization::CArchive& out) const {
  out << timestamp << sensorLabel << sensorPose << model;
}

void CObservationCameraModel::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version) {
  switch (version) {
    case 0:
      in >> timestamp >> sensorLabel >> sensorPose >> model;
      break;
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

void CObservationCameraModel::getDescriptionAsText(std::ostream& o) const {
  CObservation::getDescriptionAsText(o);
  o << "Camera model (omnisfm) of the stock CObservationImage observations labelled '"
    << sensorLabel << "' that follow; camera on the robot: " << sensorPose << "\n";
  model.getDescriptionAsText(o);
}

}  // namespace omnisfm::mrpt_plugin
