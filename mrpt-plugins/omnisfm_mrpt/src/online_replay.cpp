#include "omnisfm/mrpt_plugin/online_replay.h"

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <stdexcept>

#include "omnisfm/io/input_error.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "rawlog_observations.h"

namespace omnisfm::mrpt_plugin {
namespace {

enum class CameraKind { kNone, kTrackedFeatures, kImages };

OmniSfmEstimatorOptions estimator_options(const OnlineReplaySettings& s) {
  OmniSfmEstimatorOptions o;
  o.filter = s.filter;
  o.tracker = s.replay.tracker;
  o.camera = s.replay.camera;
  o.camera_label = s.replay.camera_label;
  o.sensor_labels = {s.replay.odometry_label, s.replay.gyro_label, s.replay.gps_label};
  o.gps_origin = s.replay.gps_origin;
  o.odometry_noise = s.odometry_noise;
  o.gyro_noise = s.gyro_noise;
  o.odometry_scale = s.odometry_scale;
  return o;
}

}  // namespace

OnlineReplaySummary replay_online(const std::string& path, const OnlineReplaySettings& settings,
                                  const OnlineReplayOutputs& outputs,
                                  const ReplayProgress& progress) {
  OmniSfmEstimator estimator(estimator_options(settings));
  estimator.onPointEnded(outputs.point_ended);
  estimator.onTrackRejected(outputs.track_rejected);
  CameraKind vision = settings.replay.vision == ReplayVision::kTrackedFeatures
                          ? CameraKind::kTrackedFeatures
                          : settings.replay.vision == ReplayVision::kImages ? CameraKind::kImages
                                                                            : CameraKind::kNone;
  use_external_images_of(path);
  RawlogReader reader(path);
  OnlineReplaySummary summary;
  std::string damage;
  std::size_t index = 0;
  const auto visit = [&](const mrpt::obs::CObservation::Ptr& observation) {
    if (!damage.empty()) return;
    const mrpt::obs::CObservation& o = *observation;
    summary.odometry += dynamic_cast<const mrpt::obs::CObservationOdometry*>(&o) != nullptr;
    summary.gyro += dynamic_cast<const mrpt::obs::CObservationIMU*>(&o) != nullptr;
    summary.gps += dynamic_cast<const mrpt::obs::CObservationGPS*>(&o) != nullptr;
    const bool features = dynamic_cast<const CObservationTrackedFeatures*>(&o) != nullptr;
    const bool image = dynamic_cast<const mrpt::obs::CObservationImage*>(&o) != nullptr;
    if ((features || image) && has_label(o, settings.replay.camera_label)) {
      const CameraKind kind = features ? CameraKind::kTrackedFeatures : CameraKind::kImages;
      if (vision == CameraKind::kNone) vision = kind;
      if (kind != vision) return;
    }
    const int frame = estimator.framesProcessed();
    try {
      estimator.processObservation(observation);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(path, 0, "object " + std::to_string(index) + ": " + e.what());
    } catch (const std::exception& e) {
      // An image that cannot be loaded or tracked: damage, as the batch replay reports it.
      damage = describe_damage(index, o.GetRuntimeClass()->className, mrpt_error_reason(e.what()));
      return;
    }
    if (estimator.framesProcessed() == frame) return;
    if (outputs.frame) outputs.frame(*estimator.filter(), frame, mrpt::Clock::toDouble(o.timestamp));
    if (progress) progress(frame + 1, 0);
  };
  mrpt::obs::CSensoryFrame none;
  while (const auto object = reader.next()) {
    index = reader.index() - 1;
    if (auto actions = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(object)) {
      for (std::size_t i = 0; i < actions->size(); ++i)
        summary.odometry +=
            dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(actions->get(i).get()) ||
            dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(actions->get(i).get());
      estimator.processActionObservation(*actions, none);
      continue;
    }
    for_each_observation(object, visit);
    if (!damage.empty()) break;
  }
  summary.read.objects = damage.empty() ? reader.index() : index;
  summary.read.problem = damage.empty() ? reader.problem() : damage;
  summary.frames = estimator.framesProcessed();
  if (estimator.filter()) summary.noise_px = estimator.filter()->pixel_sigma();
  estimator.finishStart();
  if (outputs.end && estimator.filter()) outputs.end(*estimator.filter());
  summary.read.used = static_cast<std::size_t>(summary.frames);
  summary.vision = vision == CameraKind::kTrackedFeatures ? "tracked features"
                   : vision == CameraKind::kImages         ? "images"
                                                           : "";
  return summary;
}

}  // namespace omnisfm::mrpt_plugin
