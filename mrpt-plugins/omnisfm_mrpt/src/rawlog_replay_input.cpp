#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"

#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationImage.h>

#include <algorithm>
#include <memory>

#include "eigen_poses.h"
#include "frame_time_order.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/mrpt_plugin/motion_sensor_collector.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/track/track_images.h"
#include "rawlog_observations.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The rawlog in one pass: motion sensors, tracked features, and the camera's images through the
// tracker for as long as they may be the vision (with kAuto, until tracked features turn up).
class ReplayPass {
 public:
  ReplayPass(const std::string& path, const ReplayOptions& options,
             const ReplayProgress& progress, ReplayInput* input)
      : path_(path),
        options_(options),
        progress_(progress),
        input_(input),
        collector_({options.odometry_label, options.gyro_label, options.gps_label},
                   options.gps_origin) {}

  // False at damage (an image that cannot be loaded), which `damage` then describes.
  bool add(const mrpt::serialization::CSerializable::Ptr& object, std::size_t index,
           std::string* damage) {
    if (auto actions = std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(object)) {
      for (std::size_t i = 0; i < actions->size(); ++i) collector_.add(*actions->get(i));
      return true;
    }
    for_each_observation(object, [&](const mrpt::obs::CObservation::Ptr& observation) {
      if (damage->empty()) add(observation, index, damage);
    });
    return damage->empty();
  }

  // A damaged image met while the images might not be the vision (kAuto before any tracked
  // features): it stops the tracking, and counts as damage only if the images are the vision.
  struct ImageDamage {
    std::size_t index;
    std::string problem;
  };
  const std::optional<ImageDamage>& image_damage() const { return image_damage_; }

  void finish() {
    ReplayInput& in = *input_;
    in.sensors = collector_.sensors();
    if (body_from_cam_) in.sensors.body_from_cam = *body_from_cam_;
    if (collector_.enu_frame() && !in.sensors.gps.empty())
      in.gps_origin = collector_.enu_frame()->origin();
    in.out_of_order = collector_.out_of_order();
    if (!in.camera) in.camera = first_model_;
    if (images_are_vision() && (options_.vision == ReplayVision::kImages || images_ > 0)) {
      if (!untracked_.empty()) throw io::InputError(path_, 0, untracked_);
      in.vision = "images";
      in.frame_times = std::move(image_times_);
      in.frames_with_images = tracker_ ? tracker_->frames() : 0;
      if (tracker_) in.tracks = tracker_->finish().observations;
      return;
    }
    in.vision = "tracked features";
    in.tracks = std::move(features_);
    in.frame_times = std::move(feature_times_);
    std::stable_sort(in.tracks.begin(), in.tracks.end(),
                     [](const core::TrackObservation& a, const core::TrackObservation& b) {
                       return a.frame != b.frame ? a.frame < b.frame : a.track < b.track;
                     });
  }

 private:
  bool images_are_vision() const {
    return options_.vision == ReplayVision::kImages ||
           (options_.vision == ReplayVision::kAuto && feature_times_.empty());
  }

  void add(const mrpt::obs::CObservation::Ptr& observation, std::size_t index,
           std::string* damage) {
    if (collector_.add(*observation) || !has_label(*observation, options_.camera_label) ||
        models_.note(*observation))
      return;
    if (const auto* features = dynamic_cast<const CObservationTrackedFeatures*>(observation.get())) {
      note_camera(features->sensorPose, features->model);
      if (options_.vision == ReplayVision::kImages) return;
      if (const std::string beyond = beyond_the_image(*features); !beyond.empty()) {
        *damage = describe_damage(index, features->GetRuntimeClass()->className, beyond);
        return;
      }
      const double time = mrpt::Clock::toDouble(features->timestamp);
      if (feature_times_.empty()) vision_pose_.reset();  // images tracked so far are not the vision
      require_next_frame(features->sensorPose, time, feature_times_, index);
      const int frame = static_cast<int>(feature_times_.size());
      feature_times_.push_back(time);
      append_tracked_features(*features, frame, &features_);
      // With kAuto, the images tracked so far are not the vision.
      tracker_.reset();
      image_times_.clear();
      image_damage_.reset();
      return;
    }
    const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(observation);
    if (!image) return;
    ++images_;
    if (const CCatadioptricCameraModel* model = models_.model_for(*image))
      note_camera(image->cameraPose, *model);
    else if (!body_from_cam_)
      body_from_cam_ = isometry_of(image->cameraPose);
    if (!images_are_vision() || image_damage_) return;
    const double time = mrpt::Clock::toDouble(image->timestamp);
    if (options_.vision == ReplayVision::kImages) {
      require_next_frame(image->cameraPose, time, image_times_, index);
      return track(*image, index, damage);
    }
    // With kAuto, tracked features may come and be the vision: what is wrong with the images
    // waits, as their damage does.
    std::string problem;
    try {
      require_next_frame(image->cameraPose, time, image_times_, index);
      track(*image, index, &problem);
    } catch (const io::InputError& e) {
      problem = e.what();
    }
    if (!problem.empty()) image_damage_ = ImageDamage{index, problem};
  }

  void track(mrpt::obs::CObservationImage& observation, std::size_t index, std::string* damage) {
    const auto& camera = options_.camera ? options_.camera : first_model_;
    if (!tracker_) {
      if (!camera) {
        // An error only if the images turn out to be the vision.
        if (untracked_.empty())
          untracked_ = "object " + std::to_string(index) +
                       " is a stock CObservationImage with no camera model before it "
                       "(CObservationCameraModel under its label): give the "
                       "camera file (--camera)";
        return;
      }
      if (!untracked_.empty()) return;
      tracker_ = std::make_unique<track::SequenceTracker>(*camera, options_.tracker);
    }
    const std::optional<RawlogImage> image = load_rawlog_image(observation, index, models_, damage);
    if (!image) return;
    if (const cv::Size size(camera->image_width(), camera->image_height());
        image->grey.size() != size) {
      // The wrong camera for these images, not damage: an error if they are the vision.
      untracked_ = "object " + std::to_string(index) + "'s image is " +
                   std::to_string(image->grey.cols) + "x" + std::to_string(image->grey.rows) +
                   " but the camera's is " + std::to_string(size.width) + "x" +
                   std::to_string(size.height) +
                   (options_.camera ? " (--camera): give these images' camera" : "");
      return;
    }
    track::SequenceFrame frame;
    frame.index = tracker_->frames();
    frame.image = image->grey;
    frame.timestamp = image->timestamp;
    tracker_->add(frame, path_ + ": object " + std::to_string(index));
    image_times_.push_back(image->timestamp);
    if (progress_) progress_(tracker_->frames(), 0);
  }

  // A camera frame comes after the previous one, from the camera's one pose on the robot.
  void require_next_frame(const mrpt::poses::CPose3D& pose, double time,
                          const std::vector<double>& previous_times, std::size_t index) {
    const std::string object = "object " + std::to_string(index) + ": ";
    if (!previous_times.empty())
      if (const std::string wrong = frame_time_problem(time, previous_times.back()); !wrong.empty())
        throw io::InputError(path_, 0, object + wrong);
    if (!vision_pose_) vision_pose_ = isometry_of(pose);
    if (!same_pose(isometry_of(pose), *vision_pose_))
      throw io::InputError(path_, 0,
                           object + "the camera's pose on the robot " + pose.asString() +
                               " is not the first frame's " + pose_of(*vision_pose_).asString() +
                               ": one camera label is one camera, fixed on the robot");
  }

  // Where the features carry no camera of their own, the one the replay takes still bounds their
  // pixels (reading checks them against their own): the first beyond its image, described.
  std::string beyond_the_image(const CObservationTrackedFeatures& features) const {
    const auto& camera = options_.camera ? options_.camera : first_model_;
    if (!camera) return "";
    for (const TrackedFeature& f : features.features)
      if (!camera->in_image(Eigen::Vector2d(f.u, f.v)))
        return "track " + std::to_string(f.track) + "'s pixel (" + io::format_double(f.u) + ", " +
               io::format_double(f.v) + ") lies outside the camera's " +
               std::to_string(camera->image_width()) + "x" +
               std::to_string(camera->image_height()) + " image";
    return "";
  }

  void note_camera(const mrpt::poses::CPose3D& pose, const CCatadioptricCameraModel& model) {
    if (!body_from_cam_) body_from_cam_ = isometry_of(pose);
    if (first_model_ || !model.has_camera()) return;
    first_model_ = model.camera();
    // A camera given to replace the rawlog's must be one of the same images.
    if (options_.camera && (options_.camera->image_width() != first_model_->image_width() ||
                            options_.camera->image_height() != first_model_->image_height()))
      throw io::InputError(path_, 0,
                           "its camera is " + std::to_string(first_model_->image_width()) + "x" +
                               std::to_string(first_model_->image_height()) +
                               " pixels but the one given (--camera) is " +
                               std::to_string(options_.camera->image_width()) + "x" +
                               std::to_string(options_.camera->image_height()) +
                               ": give the camera of these images");
  }

  const std::string& path_;
  const ReplayOptions& options_;
  const ReplayProgress& progress_;
  ReplayInput* input_;
  MotionSensorCollector collector_;
  std::optional<Eigen::Isometry3d> body_from_cam_;
  std::optional<Eigen::Isometry3d> vision_pose_;  // the camera's pose on the robot, first frame
  ImageCameraModels models_;
  std::optional<camera::CatadioptricCamera> first_model_;
  std::vector<core::TrackObservation> features_;
  std::vector<double> feature_times_;
  int images_ = 0;
  std::unique_ptr<track::SequenceTracker> tracker_;
  std::vector<double> image_times_;
  std::string untracked_;  // why the images could not be tracked
  std::optional<ImageDamage> image_damage_;
};

// The pass's last word: a damaged image counts only when the images are the vision.
void finish(ReplayPass& pass, ReplayInput* input) {
  pass.finish();
  if (pass.image_damage() && input->vision == "images") {
    input->read.objects = pass.image_damage()->index;
    input->read.problem = pass.image_damage()->problem;
  }
  input->read.used = input->frame_times.size();
}

}  // namespace

ReplayInput read_replay_input(const std::string& path, const ReplayOptions& options,
                              const ReplayProgress& progress) {
  ReplayInput input;
  input.camera = options.camera;
  ReplayPass pass(path, options, progress, &input);
  use_external_images_of(path);
  RawlogReader reader(path);
  std::string damage;
  while (const auto object = reader.next())
    if (!pass.add(object, reader.index() - 1, &damage)) break;
  input.read.objects = damage.empty() ? reader.index() : reader.index() - 1;
  input.read.problem = damage.empty() ? reader.problem() : damage;
  finish(pass, &input);
  return input;
}

ReplayInput read_replay_input(const mrpt::maps::CSimpleMap& map, const ReplayOptions& options,
                              const ReplayProgress& progress) {
  ReplayInput input;
  input.camera = options.camera;
  const std::string source = "the simple map";
  ReplayPass pass(source, options, progress, &input);
  std::string damage;
  size_t used = 0;
  for (; used < map.size(); ++used) {
    const auto [pose, frame] = map.get(used);
    if (!frame) continue;
    // Loading an image (its external file) changes the observation's cache, not its meaning.
    if (!pass.add(std::const_pointer_cast<mrpt::obs::CSensoryFrame>(frame), used, &damage)) break;
  }
  input.read.objects = used;
  input.read.problem = damage;
  finish(pass, &input);
  return input;
}

}  // namespace omnisfm::mrpt_plugin
