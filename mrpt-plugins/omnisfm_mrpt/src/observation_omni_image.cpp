#include "omnisfm/camera/camera_kinds.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"

#include <mrpt/serialization/CArchive.h>

#include <ostream>

#include "omnisfm/camera/pinhole_camera.h"

IMPLEMENTS_SERIALIZABLE(CObservationOmniImage, mrpt::obs::CObservationImage, omnisfm::mrpt_plugin)

namespace omnisfm::mrpt_plugin {

mrpt::img::TCamera inner_camera_params(const camera::CatadioptricCamera& camera) {
  mrpt::img::TCamera params;
  params.ncols = static_cast<uint32_t>(camera.image_width());
  params.nrows = static_cast<uint32_t>(camera.image_height());
  params.cameraName =
      std::string("omnisfm ") + camera::name_of(camera.inner().kind()) + " inner camera";
  params.distortion = mrpt::img::DistortionModel::none;
  if (const auto* pinhole = dynamic_cast<const camera::PinholeCamera*>(&camera.inner())) {
    const camera::PinholeIntrinsics& k = pinhole->intrinsics();
    params.setIntrinsicParamsFromValues(k.fx, k.fy, k.cx, k.cy);
    params.distortion = mrpt::img::DistortionModel::plumb_bob;
    params.dist = {k.k1, k.k2, k.p1, k.p2, k.k3, 0, 0, 0};
  }
  return params;
}

void CObservationOmniImage::set_camera(const camera::CatadioptricCamera& camera) {
  model.set_camera(camera);
  cameraParams = inner_camera_params(camera);
}

uint8_t CObservationOmniImage::serializeGetVersion() const { return 0; }

void CObservationOmniImage::serializeTo(mrpt::serialization::CArchive& out) const {
  // The base format's version goes first, so that a later MRPT reads what an earlier one wrote.
  out << CObservationImage::serializeGetVersion();
  CObservationImage::serializeTo(out);
  out << model;
}

void CObservationOmniImage::serializeFrom(mrpt::serialization::CArchive& in, uint8_t version) {
  switch (version) {
    case 0: {
      uint8_t image_version = 0;
      in >> image_version;
      CObservationImage::serializeFrom(in, image_version);
      in >> model;
      break;
    }
    default:
      MRPT_THROW_UNKNOWN_SERIALIZATION_VERSION(version);
  }
}

void CObservationOmniImage::getDescriptionAsText(std::ostream& o) const {
  CObservationImage::getDescriptionAsText(o);
  o << "Omnidirectional image (omnisfm): geometry from the catadioptric model below; the camera "
       "parameters above are the inner camera's lens only.\n";
  model.getDescriptionAsText(o);
}

}  // namespace omnisfm::mrpt_plugin
