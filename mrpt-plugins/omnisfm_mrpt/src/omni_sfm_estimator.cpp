#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/img/CImage.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/system/string_utils.h>

#include <algorithm>
#include <stdexcept>

#include "eigen_poses.h"
#include "frame_time_order.h"
#include "grey_image.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/sfm/sensor_ranges.h"
#include "omnisfm/sfm/settings_file.h"
#include "omnisfm/sfm/settings_ranges.h"
#include "omnisfm/track/track_images.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// map_from_robot for the filter's pose cam_from_world.
mrpt::poses::CPose3D robot_pose(const Eigen::Isometry3d& cam_from_world,
                                const Eigen::Isometry3d& body_from_cam,
                                const Eigen::Isometry3d& map_from_world) {
  return pose_of(map_from_world * cam_from_world.inverse() * body_from_cam.inverse());
}

// map_from_robot for the filter's pose moved by the error `delta` (rotation left, translation).
mrpt::poses::CPose3D perturbed_robot_pose(const Eigen::Isometry3d& cam_from_world,
                                          const Vector6d& delta,
                                          const Eigen::Isometry3d& body_from_cam,
                                          const Eigen::Isometry3d& map_from_world) {
  Eigen::Isometry3d perturbed = cam_from_world;
  const Eigen::Vector3d rotation = delta.head<3>();
  if (rotation.norm() > 0)
    perturbed.linear() =
        Eigen::AngleAxisd(rotation.norm(), rotation.normalized()).toRotationMatrix() *
        cam_from_world.linear();
  perturbed.translation() += delta.tail<3>();
  return robot_pose(perturbed, body_from_cam, map_from_world);
}

}  // namespace

mrpt::poses::CPose3DPDFGaussian robot_pose_of(const Eigen::Isometry3d& cam_from_world,
                                              const Eigen::Matrix<double, 6, 6>& covariance,
                                              const Eigen::Isometry3d& body_from_cam,
                                              const Eigen::Isometry3d& map_from_world) {
  const mrpt::poses::CPose3D mean =
      perturbed_robot_pose(cam_from_world, Vector6d::Zero(), body_from_cam, map_from_world);
  const auto perturbed = [&](const Vector6d& delta) {
    return perturbed_robot_pose(cam_from_world, delta, body_from_cam, map_from_world);
  };
  const Eigen::Matrix<double, 6, 6> J = mrpt_parameters_jacobian<6>(perturbed, Vector6d::Zero());
  mrpt::poses::CPose3DPDFGaussian pdf;
  pdf.mean = mean;
  pdf.cov = mrpt::math::CMatrixDouble66(Eigen::Matrix<double, 6, 6>(J * covariance * J.transpose()));
  return pdf;
}

namespace {

// `name` of `source` as omnisfm's INI sections are read: each value without a trailing comment.
io::IniSection section_of(const mrpt::config::CConfigFileBase& source, const std::string& name) {
  std::string file = "(INI text)";
  if (const auto* f = dynamic_cast<const mrpt::config::CConfigFile*>(&source))
    file = f->getAssociatedFile();
  io::IniSection section(file, name, 0);
  std::vector<std::string> keys;
  source.getAllKeys(name, keys);
  for (const std::string& key : keys) {
    std::string value = source.read_string(name, key, "");
    value = value.substr(0, std::min({value.find('#'), value.find(';'), value.find("//")}));
    section.set(key, mrpt::system::trim(value));
  }
  return section;
}

}  // namespace

RunOptions OmniSfmEstimatorOptions::run_options() const {
  RunOptions run;
  run.replay.tracker = tracker;
  run.replay.vision = vision;
  run.replay.camera_label = camera_label;
  run.replay.odometry_label = sensor_labels.odometry;
  run.replay.gyro_label = sensor_labels.gyro;
  run.replay.gps_label = sensor_labels.gps;
  run.replay.gps_origin = gps_origin;
  run.odometry_noise = odometry_noise;
  run.gyro_noise = gyro_noise;
  run.odometry_scale = odometry_scale;
  run.keyframe_distance_m = keyframe_distance_m;
  run.keyframe_angle_rad = keyframe_angle_rad;
  return run;
}

std::string OmniSfmEstimatorOptions::problem() const {
  if (const std::string wrong = sfm::settings_problem(filter); !wrong.empty())
    return "OmniSfmEstimatorOptions::filter: " + wrong;
  sfm::MotionSensors sensors;
  set_sensor_noises(&sensors);
  if (const std::string wrong = sfm::sensors_problem(sensors); !wrong.empty())
    return "OmniSfmEstimatorOptions: " + wrong;
  return "";
}

void OmniSfmEstimatorOptions::set_sensor_noises(sfm::MotionSensors* sensors) const {
  sensors->odometry_noise = odometry_noise;
  sensors->gyro_noise = gyro_noise;
  sensors->odometry_scale = odometry_scale;
}

void OmniSfmEstimatorOptions::set_run_options(const RunOptions& run) {
  tracker = run.replay.tracker;
  vision = run.replay.vision;
  camera_label = run.replay.camera_label;
  sensor_labels = {run.replay.odometry_label, run.replay.gyro_label, run.replay.gps_label};
  gps_origin = run.replay.gps_origin;
  odometry_noise = run.odometry_noise;
  gyro_noise = run.gyro_noise;
  odometry_scale = run.odometry_scale;
  keyframe_distance_m = run.keyframe_distance_m;
  keyframe_angle_rad = run.keyframe_angle_rad;
}

void OmniSfmEstimatorOptions::loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                                                 const std::string& section) {
  RunOptions run = run_options();
  read_run_options(section_of(source, section), &run);
  sfm::FilterSettings read_filter = filter;
  if (section != "sfm" && source.sectionExists("sfm")) {
    const io::IniSection sfm_section = section_of(source, "sfm");
    const sfm::SfmSettings read = sfm::read_sfm_settings(sfm_section);
    // The camera comes with the options or the observations, neither of which a config file's
    // key can give a covariance.
    if (read.consider_camera)
      sfm_section.fail("consider_camera",
                       "the estimator takes the camera's covariance from its options "
                       "(OmniSfmEstimatorOptions::filter.camera_uncertainty), not from a key");
    read_filter = read.filter;
  }
  set_run_options(run);
  filter = read_filter;
}

void OmniSfmEstimatorOptions::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                               const std::string& section) const {
  const io::IniSection keys = run_options_section(run_options(), section);
  for (const io::IniEntry& entry : keys.entries()) target.write(section, entry.key, entry.value);
}

OmniSfmEstimator::OmniSfmEstimator(const OmniSfmEstimatorOptions& estimator_options)
    : options_(estimator_options),
      collector_(estimator_options.sensor_labels, estimator_options.gps_origin) {
  // Said here rather than at the first camera observation, where the filter starts.
  if (const std::string problem = options_.problem(); !problem.empty())
    throw std::invalid_argument(problem);
  initialize();
}

OmniSfmEstimator::~OmniSfmEstimator() = default;

void OmniSfmEstimator::initialize(const mrpt::maps::CSimpleMap& initialMap,
                                  const mrpt::poses::CPosePDF* x0) {
  if (!initialMap.empty())
    throw std::invalid_argument("OmniSfmEstimator builds its own map: it takes no initial map");
  collector_ = MotionSensorCollector(options_.sensor_labels, options_.gps_origin);
  options_.set_sensor_noises(&collector_.sensors());
  filter_.reset();
  tracker_.reset();
  image_models_ = ImageCameraModels();
  body_from_cam_ = Eigen::Isometry3d::Identity();
  map_from_start_ = Eigen::Isometry3d::Identity();
  if (x0) map_from_start_ = isometry_of(mrpt::poses::CPose3D(x0->getMeanVal()));
  keyframes_.clear();
  frames_ = 0;
  previous_frame_time_ = 0;
}

bool OmniSfmEstimator::is_camera(const mrpt::obs::CObservation& observation) const {
  return options_.camera_label.empty() || observation.sensorLabel == options_.camera_label;
}

void OmniSfmEstimator::start(const camera::CatadioptricCamera& camera,
                             const mrpt::poses::CPose3D& camera_pose) {
  body_from_cam_ = isometry_of(camera_pose);
  collector_.sensors().body_from_cam = body_from_cam_;
  filter_ = std::make_unique<sfm::OnlineFilter>(camera, options_.filter);
  if (point_ended_) filter_->on_point_ended(point_ended_);
  if (track_rejected_) filter_->on_track_rejected(track_rejected_);
}

void OmniSfmEstimator::require_next_frame(const mrpt::poses::CPose3D& pose,
                                          double timestamp) const {
  if (frames_ > 0)
    if (const std::string wrong = frame_time_problem(timestamp, previous_frame_time_);
        !wrong.empty())
      throw std::invalid_argument(wrong);
  if (!same_pose(isometry_of(pose), body_from_cam_))
    throw std::invalid_argument(
        "the camera's pose on the robot " + pose.asString() + " is not the first frame's " +
        pose_of(body_from_cam_).asString() +
        ": one camera label is one camera, fixed on the robot");
}

void OmniSfmEstimator::process_frame(const std::vector<sfm::TrackPixel>& pixels,
                                     double timestamp,
                                     const mrpt::obs::CObservation::Ptr& observation) {
  const sfm::MotionSensors& sensors = collector_.sensors();
  if (frames_ > 0 && (!sensors.odometry.empty() || !sensors.gyro.empty())) {
    const long refused = filter_->refused_motions();
    filter_->process_frame(frames_, pixels,
                           sfm::predict_camera_motion(sensors, previous_frame_time_, timestamp,
                                                      options_.filter, filter_->sensor_states()));
    if (filter_->refused_motions() > refused)
      MRPT_LOG_WARN_STREAM("frame at " << io::format_double(timestamp)
                                       << " s: the images showed the motion the vehicle's "
                                          "sensors predicted wrong, grossly or for good; "
                                          "the filter took its own prediction");
  } else
    filter_->process_frame(frames_, pixels);
  previous_frame_time_ = timestamp;
  collector_.forget_before(timestamp);  // an endless run keeps no sensor history
  ++frames_;
  if (options.enableMapUpdating) maybe_add_keyframe(observation);
}

void OmniSfmEstimator::maybe_add_keyframe(const mrpt::obs::CObservation::Ptr& observation) {
  // The mean alone each frame; the covariance only for a keyframe.
  const mrpt::poses::CPose3D pose =
      robot_pose(filter_->cam_from_world(), body_from_cam_, mapFromWorld());
  if (keyframes_.size() > 0) {
    const mrpt::poses::CPose3D moved = pose - last_keyframe_pose_;
    const double turned = Eigen::AngleAxisd(isometry_of(moved).linear()).angle();
    if (moved.norm() < options_.keyframe_distance_m && turned < options_.keyframe_angle_rad &&
        !options.debugForceInsertion)
      return;
  }
  auto pdf = std::make_shared<mrpt::poses::CPose3DPDFGaussian>();
  getCurrentPoseEstimation(*pdf);
  auto frame = std::make_shared<mrpt::obs::CSensoryFrame>();
  frame->insert(observation);
  keyframes_.insert(pdf, frame);
  last_keyframe_pose_ = pdf->mean;
}

void OmniSfmEstimator::processActionObservation(mrpt::obs::CActionCollection& action,
                                                mrpt::obs::CSensoryFrame& observations) {
  for (std::size_t i = 0; i < action.size(); ++i) collector_.add(*action.get(i));
  for (const auto& observation : observations) processObservation(observation);
}

void OmniSfmEstimator::processObservation(const mrpt::obs::CObservation::Ptr& observation) {
  if (!observation || collector_.add(*observation) || !is_camera(*observation) ||
      image_models_.note(*observation))
    return;
  if (const auto features = std::dynamic_pointer_cast<CObservationTrackedFeatures>(observation)) {
    if (tracker_) return;  // the camera's images came first: they are the vision
    if (filter_)
      require_next_frame(features->sensorPose, mrpt::Clock::toDouble(features->timestamp));
    if (!filter_) {
      if (!options_.camera && !features->model.has_camera())
        throw std::invalid_argument("tracked features without a camera model: give the camera");
      start(options_.camera ? *options_.camera : features->model.camera(), features->sensorPose);
    }
    // Features of other images than the camera's are refused, as the batch replay refuses them.
    const camera::CatadioptricCamera& camera = filter_->camera();
    const auto size_text = [](const camera::CatadioptricCamera& c) {
      return std::to_string(c.image_width()) + "x" + std::to_string(c.image_height());
    };
    if (features->model.has_camera() &&
        (features->model.camera().image_width() != camera.image_width() ||
         features->model.camera().image_height() != camera.image_height()))
      throw std::invalid_argument("the features' camera is " + size_text(features->model.camera()) +
                                  " pixels but the estimator's is " + size_text(camera) +
                                  ": give the camera of these images");
    std::vector<sfm::TrackPixel> pixels;
    for (const TrackedFeature& f : features->features) {
      const Eigen::Vector2d pixel(f.u, f.v);
      if (!camera.in_image(pixel))
        throw std::invalid_argument("track " + std::to_string(f.track) + "'s pixel (" +
                                    io::format_double(f.u) + ", " + io::format_double(f.v) +
                                    ") lies outside the camera's " + size_text(camera) + " image");
      pixels.push_back({f.track, pixel});
    }
    process_frame(pixels, mrpt::Clock::toDouble(features->timestamp), observation);
  } else if (const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(observation)) {
    if (filter_ && !tracker_) return;  // tracked features came first: they are the vision
    if (filter_) require_next_frame(image->cameraPose, mrpt::Clock::toDouble(image->timestamp));
    if (!filter_) {
      std::optional<camera::CatadioptricCamera> camera = options_.camera;
      if (const CCatadioptricCameraModel* model = image_models_.model_for(*image))
        if (!camera) camera = model->camera();
      if (!camera)
        throw std::invalid_argument(
            "a stock CObservationImage with no camera model before it (CObservationCameraModel "
            "under its label): give the camera");
      start(*camera, image->cameraPose);
      tracker_ = std::make_unique<track::SequenceTracker>(*camera, options_.tracker);
    }
    image->load();
    track::SequenceFrame frame;
    frame.index = tracker_->frames();
    frame.image = grey_of(image->image);
    process_frame(tracker_->add(frame, image->sensorLabel), mrpt::Clock::toDouble(image->timestamp),
                  observation);
  }
}

void OmniSfmEstimator::getCurrentPoseEstimation(mrpt::poses::CPose3DPDFGaussian& out) const {
  if (!filter_) {
    out = mrpt::poses::CPose3DPDFGaussian(pose_of(map_from_start_));
    return;
  }
  out = robot_pose_of(filter_->cam_from_world(), filter_->pose_covariance(), body_from_cam_,
                      mapFromWorld());
}

mrpt::poses::CPose3DPDF::Ptr OmniSfmEstimator::getCurrentPoseEstimation() const {
  auto pdf = std::make_shared<mrpt::poses::CPose3DPDFGaussian>();
  getCurrentPoseEstimation(*pdf);
  return pdf;
}

std::map<int, Eigen::Vector3d> OmniSfmEstimator::points() const {
  std::map<int, Eigen::Vector3d> in_map;
  if (!filter_) return in_map;
  const Eigen::Isometry3d map_from_world = mapFromWorld();
  for (const auto& [track, p] : filter_->points()) in_map[track] = map_from_world * p;
  return in_map;
}

std::map<int, mrpt::poses::CPose3D> OmniSfmEstimator::smoothedStartPoses() const {
  std::map<int, mrpt::poses::CPose3D> in_map;
  if (!filter_) return in_map;
  const Eigen::Isometry3d map_from_world = mapFromWorld();
  for (const auto& [frame, cam_from_world] : filter_->smoothed_start())
    in_map[frame] = robot_pose(cam_from_world, body_from_cam_, map_from_world);
  return in_map;
}

void OmniSfmEstimator::getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out) const {
  out = keyframes_;
}

unsigned int OmniSfmEstimator::getCurrentlyBuiltMapSize() {
  return static_cast<unsigned int>(keyframes_.size());
}

const mrpt::maps::CMultiMetricMap* OmniSfmEstimator::getCurrentlyBuiltMetricMap() const {
  auto cloud = mrpt::maps::CSimplePointsMap::Create();
  for (const auto& [track, p] : points())
    cloud->insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()),
                       static_cast<float>(p.z()));
  metric_map_.maps.clear();
  metric_map_.maps.push_back(cloud);
  return &metric_map_;
}

void OmniSfmEstimator::saveCurrentEstimationToImage(const std::string& file, bool) {
  std::vector<Eigen::Vector2d> path, cloud;
  for (size_t k = 0; k < keyframes_.size(); ++k) {
    const auto& [pdf, frame] = keyframes_.get(k);
    const mrpt::poses::CPose3D mean = pdf->getMeanVal();
    path.emplace_back(mean.x(), mean.y());
  }
  mrpt::poses::CPose3DPDFGaussian now;
  getCurrentPoseEstimation(now);
  path.emplace_back(now.mean.x(), now.mean.y());
  for (const auto& [track, p] : points()) cloud.emplace_back(p.x(), p.y());
  Eigen::AlignedBox2d box;
  for (const auto& p : path) box.extend(p);
  for (const auto& p : cloud) box.extend(p);
  constexpr int kSize = 800, kMargin = 20;
  const double span = std::max(box.sizes().maxCoeff(), 1e-3);
  const double scale = (kSize - 2 * kMargin) / span;
  const auto to_pixel = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2i(kMargin + static_cast<int>((p.x() - box.min().x()) * scale),
                           kSize - kMargin - static_cast<int>((p.y() - box.min().y()) * scale));
  };
  mrpt::img::CImage image(kSize, kSize, mrpt::img::CH_RGB);
  image.filledRectangle(0, 0, kSize - 1, kSize - 1, mrpt::img::TColor(255, 255, 255));
  for (const auto& p : cloud) {
    const Eigen::Vector2i q = to_pixel(p);
    image.filledRectangle(q.x() - 1, q.y() - 1, q.x() + 1, q.y() + 1, mrpt::img::TColor(0, 0, 0));
  }
  for (size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2i a = to_pixel(path[i - 1]), b = to_pixel(path[i]);
    image.line(a.x(), a.y(), b.x(), b.y(), mrpt::img::TColor(0, 0, 255), 2);
  }
  const Eigen::Vector2i robot = to_pixel(path.back());
  image.drawCircle(robot.x(), robot.y(), 6, mrpt::img::TColor(255, 0, 0), 2);
  if (!image.saveToFile(file)) throw std::runtime_error(file + ": the image cannot be saved");
}

}  // namespace omnisfm::mrpt_plugin
