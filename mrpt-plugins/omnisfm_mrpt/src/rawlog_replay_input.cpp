#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <algorithm>
#include <memory>

#include "omnisfm/io/input_error.h"
#include "omnisfm/mrpt_plugin/motion_sensor_collector.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/track/track_images.h"

#include "eigen_poses.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The first pass: motion sensors, tracked features, and what the images say about the camera.
class RawlogScan {
 public:
  RawlogScan(const ReplayOptions& options, ReplayInput* input)
      : options_(options),
        input_(input),
        collector_({options.odometry_label, options.gyro_label, options.gps_label},
                   options.gps_origin) {}

  void add(const mrpt::serialization::CSerializable::Ptr& object) {
    if (auto observation = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object)) {
      add(*observation);
    } else if (auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object)) {
      for (const auto& member : *frame) add(*member);
    } else if (auto actions = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(object)) {
      for (std::size_t i = 0; i < actions->size(); ++i) collector_.add(*actions->get(i));
    }
  }

  void finish() {
    input_->sensors = collector_.sensors();
    if (body_from_cam_) input_->sensors.body_from_cam = *body_from_cam_;
    if (collector_.enu_frame() && !input_->sensors.gps.empty())
      input_->gps_origin = collector_.enu_frame()->origin();
    input_->out_of_order = collector_.out_of_order();
    if (!input_->camera) input_->camera = first_model_;
  }

  int images() const { return images_; }
  const std::vector<io::TrackObservation>& tracks() const { return tracks_; }
  const std::vector<double>& tracked_frame_times() const { return tracked_frame_times_; }

 private:
  bool is_camera(const mrpt::obs::CObservation& observation) const {
    return options_.camera_label.empty() || observation.sensorLabel == options_.camera_label;
  }

  void add(const mrpt::obs::CObservation& observation) {
    if (collector_.add(observation)) return;
    if (const auto* features = dynamic_cast<const CObservationTrackedFeatures*>(&observation)) {
      if (!is_camera(observation)) return;
      const int frame = static_cast<int>(tracked_frame_times_.size());
      tracked_frame_times_.push_back(mrpt::Clock::toDouble(features->timestamp));
      for (const TrackedFeature& f : features->features)
        tracks_.push_back({frame, f.track, Eigen::Vector2d(f.u, f.v)});
      note_camera(features->sensorPose, features->model);
    } else if (const auto* image = dynamic_cast<const mrpt::obs::CObservationImage*>(&observation)) {
      if (!is_camera(observation)) return;
      ++images_;
      if (const auto* omni = dynamic_cast<const CObservationOmniImage*>(image))
        note_camera(image->cameraPose, omni->model);
      else if (!body_from_cam_)
        body_from_cam_ = isometry_of(image->cameraPose);
    }
  }

  void note_camera(const mrpt::poses::CPose3D& pose, const CCatadioptricCameraModel& model) {
    if (!body_from_cam_) body_from_cam_ = isometry_of(pose);
    if (!first_model_ && model.has_camera()) first_model_ = model.camera();
  }

  const ReplayOptions& options_;
  ReplayInput* input_;
  MotionSensorCollector collector_;
  std::optional<Eigen::Isometry3d> body_from_cam_;
  std::optional<camera::CatadioptricCamera> first_model_;
  std::vector<io::TrackObservation> tracks_;
  std::vector<double> tracked_frame_times_;
  int images_ = 0;
};

// The second pass, for images: every camera image through the tracker, in file order.
void track_rawlog_images(const std::string& path, const ReplayOptions& options, int images,
                         const ReplayProgress& progress, ReplayInput* input) {
  std::unique_ptr<track::SequenceTracker> tracker;
  const RawlogReadResult read = for_each_rawlog_image(
      path,
      [&](RawlogImage& image) {
        if (!tracker) {
          if (!input->camera) input->camera = image.camera;
          if (!input->camera)
            throw io::InputError(path, 0,
                                 "object " + std::to_string(image.object_index) +
                                     " is a stock CObservationImage, which carries no camera "
                                     "model: give the camera file (--camera)");
          tracker = std::make_unique<track::SequenceTracker>(*input->camera, options.tracker);
        }
        track::SequenceFrame frame;
        frame.index = tracker->frames();
        frame.image = image.grey;
        frame.timestamp = image.timestamp;
        tracker->add(frame, path + ": object " + std::to_string(image.object_index));
        input->frame_times.push_back(image.timestamp);
        if (progress) progress(tracker->frames(), images);
      },
      options.camera_label);
  if (!read.complete()) input->read = read;
  input->frames_with_images = tracker ? tracker->frames() : 0;
  if (tracker) input->tracks = tracker->finish().observations;
}

}  // namespace

ReplayInput read_replay_input(const std::string& path, const ReplayOptions& options,
                              const ReplayProgress& progress) {
  ReplayInput input;
  input.camera = options.camera;
  RawlogScan scan(options, &input);
  {
    RawlogReader reader(path);
    while (const auto object = reader.next()) scan.add(object);
    input.read.objects = reader.index();
    input.read.problem = reader.problem();
  }
  scan.finish();

  const bool use_images =
      options.vision == ReplayVision::kImages ||
      (options.vision == ReplayVision::kAuto && scan.tracks().empty() && scan.images() > 0);
  if (use_images) {
    input.vision = "images";
    track_rawlog_images(path, options, scan.images(), progress, &input);
  } else {
    input.vision = "tracked features";
    input.tracks = scan.tracks();
    input.frame_times = scan.tracked_frame_times();
    std::stable_sort(input.tracks.begin(), input.tracks.end(),
                     [](const io::TrackObservation& a, const io::TrackObservation& b) {
                       return a.frame != b.frame ? a.frame < b.frame : a.track < b.track;
                     });
  }
  input.read.used = input.frame_times.size();
  return input;
}

}  // namespace omnisfm::mrpt_plugin
