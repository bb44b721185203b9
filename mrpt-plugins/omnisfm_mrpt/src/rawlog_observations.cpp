#include "rawlog_observations.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <filesystem>

#include "eigen_poses.h"
#include "grey_image.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"

namespace omnisfm::mrpt_plugin {
namespace {

// Where MRPT's tools look for a rawlog's external images (CRawlog::detectImagesDirectory, which
// MRPT 2.5 gets wrong: it drops the separator between folder and file name).
std::string external_images_folder(const std::string& rawlog_path) {
  const std::filesystem::path path = std::filesystem::absolute(rawlog_path).lexically_normal();
  const std::string stem = path.stem().string();
  for (const char* suffix : {"_Images", "_images", "_IMAGES"}) {
    const std::filesystem::path folder = path.parent_path() / (stem + suffix);
    std::error_code ec;
    if (std::filesystem::is_directory(folder, ec)) return folder.string();
  }
  return (path.parent_path() / "Images").string();
}

}  // namespace

void for_each_observation(const mrpt::serialization::CSerializable::Ptr& object,
                          const std::function<void(const mrpt::obs::CObservation::Ptr&)>& visit) {
  if (auto observation = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object)) {
    visit(observation);
  } else if (auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
    for (const auto& member : *frame) visit(member);
  }
}

void use_external_images_of(const std::string& rawlog_path) {
  mrpt::img::CImage::setImagesPathBase(external_images_folder(rawlog_path));
}

std::optional<RawlogImage> load_rawlog_image(mrpt::obs::CObservationImage& image,
                                             std::size_t index, const ImageCameraModels& models,
                                             std::string* damage) {
  RawlogImage out;
  try {
    image.load();
    out.grey = grey_of(image.image);
  } catch (const std::exception& error) {
    *damage = describe_damage(index, image.GetRuntimeClass()->className,
                              "its image cannot be loaded: " + mrpt_error_reason(error.what()));
    return std::nullopt;
  }
  out.object_index = index;
  out.timestamp = mrpt::Clock::toDouble(image.timestamp);
  out.sensor_label = image.sensorLabel;
  out.robot_from_cam = isometry_of(image.cameraPose);
  if (const CCatadioptricCameraModel* model = models.model_for(image)) out.camera = model->camera();
  return out;
}

void append_tracked_features(const CObservationTrackedFeatures& features, int frame,
                             std::vector<core::TrackObservation>* observations) {
  for (const TrackedFeature& f : features.features)
    observations->push_back({frame, f.track, Eigen::Vector2d(f.u, f.v)});
}

bool has_label(const mrpt::obs::CObservation& observation, const std::string& label) {
  return label.empty() || observation.sensorLabel == label;
}

}  // namespace omnisfm::mrpt_plugin
