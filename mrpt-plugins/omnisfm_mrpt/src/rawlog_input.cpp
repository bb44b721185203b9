#include "omnisfm/mrpt_plugin/rawlog_input.h"

#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <filesystem>
#include <opencv2/core.hpp>

#include "grey_image.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"

#include "eigen_poses.h"

namespace omnisfm::mrpt_plugin {
namespace {

using ObservationVisitor = std::function<void(const mrpt::obs::CObservation::Ptr&)>;

// An observation object is itself; a sensory frame holds several; actions hold none.
void for_each_observation(const mrpt::serialization::CSerializable::Ptr& object,
                          const ObservationVisitor& visit) {
  if (auto observation = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object)) {
    visit(observation);
  } else if (auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
    for (const auto& member : *frame) visit(member);
  }
}

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

bool wanted(const mrpt::obs::CObservation& observation, const std::string& sensor_label) {
  return sensor_label.empty() || observation.sensorLabel == sensor_label;
}

}  // namespace

RawlogReadResult for_each_rawlog_image(const std::string& path,
                                       const std::function<void(RawlogImage&)>& visit,
                                       const std::string& sensor_label) {
  mrpt::img::CImage::setImagesPathBase(external_images_folder(path));
  RawlogReader reader(path);
  RawlogReadResult result;
  while (const auto object = reader.next()) {
    const std::size_t index = reader.index() - 1;
    std::string damage;
    for_each_observation(object, [&](const mrpt::obs::CObservation::Ptr& observation) {
      const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(observation);
      if (!image || !damage.empty() || !wanted(*image, sensor_label)) return;
      RawlogImage out;
      try {
        image->load();
        out.grey = grey_of(image->image);
      } catch (const std::exception& error) {
        damage = describe_damage(path, index, image->GetRuntimeClass()->className,
                                 "its image cannot be loaded: " + mrpt_error_reason(error.what()));
        return;
      }
      out.object_index = index;
      out.timestamp = mrpt::Clock::toDouble(image->timestamp);
      out.sensor_label = image->sensorLabel;
      out.robot_from_cam = isometry_of(image->cameraPose);
      if (const auto omni = std::dynamic_pointer_cast<CObservationOmniImage>(image))
        if (omni->model.has_camera()) out.camera = omni->model.camera();
      visit(out);
      ++result.used;
    });
    if (!damage.empty()) {
      result.objects = index;
      result.problem = damage;
      return result;
    }
  }
  result.objects = reader.index();
  result.problem = reader.problem();
  return result;
}

RawlogReadResult read_rawlog_tracks(const std::string& path, RawlogTracks* tracks,
                                    const std::string& sensor_label) {
  RawlogReader reader(path);
  RawlogReadResult result;
  while (const auto object = reader.next()) {
    for_each_observation(object, [&](const mrpt::obs::CObservation::Ptr& observation) {
      const auto features = std::dynamic_pointer_cast<CObservationTrackedFeatures>(observation);
      if (!features || !wanted(*features, sensor_label)) return;
      tracks->frames.push_back({features->frame, mrpt::Clock::toDouble(features->timestamp)});
      for (const TrackedFeature& f : features->features)
        tracks->observations.push_back({features->frame, f.track, Eigen::Vector2d(f.u, f.v)});
      if (!tracks->camera && features->model.has_camera())
        tracks->camera = features->model.camera();
      ++result.used;
    });
  }
  result.objects = reader.index();
  result.problem = reader.problem();
  return result;
}

}  // namespace omnisfm::mrpt_plugin
