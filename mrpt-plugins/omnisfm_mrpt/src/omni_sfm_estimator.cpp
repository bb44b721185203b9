#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"

#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationImage.h>

#include <stdexcept>

#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/track/track_images.h"

#include "eigen_poses.h"
#include "grey_image.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

Vector6d mrpt_vector_of(const mrpt::poses::CPose3D& p) {
  Vector6d v;
  v << p.x(), p.y(), p.z(), p.yaw(), p.pitch(), p.roll();
  return v;
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
  return pose_of(map_from_world * perturbed.inverse() * body_from_cam.inverse());
}

}  // namespace

mrpt::poses::CPose3DPDFGaussian robot_pose_of(const Eigen::Isometry3d& cam_from_world,
                                              const Eigen::Matrix<double, 6, 6>& covariance,
                                              const Eigen::Isometry3d& body_from_cam,
                                              const Eigen::Isometry3d& map_from_world) {
  const mrpt::poses::CPose3D mean =
      perturbed_robot_pose(cam_from_world, Vector6d::Zero(), body_from_cam, map_from_world);
  // Central differences: the map is smooth away from pitch = +-90 degrees, and a step of 1e-6
  // leaves errors near 1e-10, far below any covariance a filter reports.
  constexpr double kStep = 1e-6;
  Eigen::Matrix<double, 6, 6> J;
  for (int k = 0; k < 6; ++k) {
    Vector6d step = Vector6d::Zero();
    step[k] = kStep;
    const Vector6d plus = mrpt_vector_of(
        perturbed_robot_pose(cam_from_world, step, body_from_cam, map_from_world));
    const Vector6d minus = mrpt_vector_of(
        perturbed_robot_pose(cam_from_world, -step, body_from_cam, map_from_world));
    Vector6d difference = plus - minus;
    for (int a = 3; a < 6; ++a) difference[a] = mrpt::math::wrapToPi(difference[a]);
    J.col(k) = difference / (2 * kStep);
  }
  mrpt::poses::CPose3DPDFGaussian pdf;
  pdf.mean = mean;
  pdf.cov = mrpt::math::CMatrixDouble66(Eigen::Matrix<double, 6, 6>(J * covariance * J.transpose()));
  return pdf;
}

OmniSfmEstimator::OmniSfmEstimator(const OmniSfmEstimatorOptions& options)
    : options_(options), collector_(options.sensor_labels, options.gps_origin) {
  sfm::MotionSensors& sensors = collector_.sensors();
  sensors.odometry_noise = options.odometry_noise;
  sensors.gyro_noise = options.gyro_noise;
  sensors.odometry_scale = options.odometry_scale;
}

OmniSfmEstimator::~OmniSfmEstimator() = default;

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

void OmniSfmEstimator::process_frame(const std::vector<sfm::TrackPixel>& pixels,
                                     double timestamp) {
  const sfm::MotionSensors& sensors = collector_.sensors();
  if (frames_ > 0 && (!sensors.odometry.empty() || !sensors.gyro.empty()))
    filter_->process_frame(frames_, pixels,
                           sfm::predict_camera_motion(sensors, previous_frame_time_, timestamp,
                                                      options_.filter, filter_->sensor_states()));
  else
    filter_->process_frame(frames_, pixels);
  previous_frame_time_ = timestamp;
  collector_.forget_before(timestamp);  // an endless run keeps no sensor history
  ++frames_;
}

void OmniSfmEstimator::processActionObservation(mrpt::obs::CActionCollection& action,
                                                mrpt::obs::CSensoryFrame& observations) {
  for (std::size_t i = 0; i < action.size(); ++i) collector_.add(*action.get(i));
  for (const auto& observation : observations) processObservation(observation);
}

void OmniSfmEstimator::processObservation(const mrpt::obs::CObservation::Ptr& observation) {
  if (!observation || collector_.add(*observation) || !is_camera(*observation)) return;
  if (const auto features = std::dynamic_pointer_cast<CObservationTrackedFeatures>(observation)) {
    if (!filter_) {
      if (!options_.camera && !features->model.has_camera())
        throw std::invalid_argument("tracked features without a camera model: give the camera");
      start(options_.camera ? *options_.camera : features->model.camera(), features->sensorPose);
    }
    std::vector<sfm::TrackPixel> pixels;
    for (const TrackedFeature& f : features->features)
      pixels.push_back({f.track, Eigen::Vector2d(f.u, f.v)});
    process_frame(pixels, mrpt::Clock::toDouble(features->timestamp));
  } else if (const auto image = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(observation)) {
    if (!filter_) {
      std::optional<camera::CatadioptricCamera> camera = options_.camera;
      if (const auto omni = std::dynamic_pointer_cast<CObservationOmniImage>(image))
        if (!camera && omni->model.has_camera()) camera = omni->model.camera();
      if (!camera)
        throw std::invalid_argument(
            "a stock CObservationImage carries no camera model: give the camera");
      start(*camera, image->cameraPose);
      tracker_ = std::make_unique<track::SequenceTracker>(*camera, options_.tracker);
    }
    if (!tracker_)
      throw std::invalid_argument("images and tracked features from one camera: use one kind");
    image->load();
    track::SequenceFrame frame;
    frame.index = tracker_->frames();
    frame.image = grey_of(image->image);
    std::vector<sfm::TrackPixel> pixels;
    for (const track::TrackedPoint& p : tracker_->add(frame, image->sensorLabel))
      pixels.push_back({p.track, p.pixel});
    process_frame(pixels, mrpt::Clock::toDouble(image->timestamp));
  }
}

void OmniSfmEstimator::getCurrentPoseEstimation(mrpt::poses::CPose3DPDFGaussian& out) const {
  if (!filter_) {
    out = mrpt::poses::CPose3DPDFGaussian();
    return;
  }
  out = robot_pose_of(filter_->cam_from_world(), filter_->pose_covariance(), body_from_cam_,
                      body_from_cam_);
}

mrpt::poses::CPose3DPDFGaussian::Ptr OmniSfmEstimator::getCurrentPoseEstimation() const {
  auto pdf = std::make_shared<mrpt::poses::CPose3DPDFGaussian>();
  getCurrentPoseEstimation(*pdf);
  return pdf;
}

std::map<int, Eigen::Vector3d> OmniSfmEstimator::points() const {
  std::map<int, Eigen::Vector3d> in_map;
  if (!filter_) return in_map;
  for (const auto& [track, p] : filter_->points()) in_map[track] = body_from_cam_ * p;
  return in_map;
}

}  // namespace omnisfm::mrpt_plugin
