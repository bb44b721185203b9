#include "omnisfm/mrpt_plugin/slam_rawlog.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "eigen_poses.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/mrpt_plugin/pose_graph_file.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The step of the central differences of a ray over its pixel: the rays are smooth over pixels,
// and half a pixel keeps the differences inside the image's valid region near its rim.
constexpr double kPixelStep = 0.5;

// The point at `depth` along the reflected ray of `pixel`; false where there is no ray.
bool point_on_ray(const camera::CatadioptricCamera& camera, const Eigen::Vector2d& pixel,
                  double depth, Eigen::Vector3d* point) {
  Eigen::Vector3d origin, direction;
  if (!camera.unproject(pixel, &origin, &direction)) return false;
  *point = origin + depth * direction;
  return true;
}

// The covariance of cam_from_world * point, the frame's pose and the point both uncertain.
Eigen::Matrix3d point_in_camera_covariance(const sfm::BatchResult& batch, int frame, int track,
                                           const Eigen::Vector3d& point,
                                           const Eigen::Matrix3d& point_covariance,
                                           bool pose_uncertain) {
  const core::PoseVector& pose = batch.cam_from_world_parameters[static_cast<size_t>(frame)];
  const Eigen::Matrix3d R = core::isometry_of(pose).linear();
  if (!pose_uncertain) return R * point_covariance * R.transpose();
  Eigen::Matrix<double, 3, 9> J;  // d (cam_from_world * point) / d (point, pose parameters)
  J.leftCols<3>() = R;
  constexpr double kStep = 1e-6;
  for (int i = 0; i < 6; ++i) {
    Eigen::Matrix<double, 6, 1> plus = pose, minus = pose;
    plus[i] += kStep;
    minus[i] -= kStep;
    J.col(3 + i) =
        (core::isometry_of(plus) * point - core::isometry_of(minus) * point) / (2 * kStep);
  }
  Eigen::Matrix<double, 9, 9> joint = Eigen::Matrix<double, 9, 9>::Zero();
  joint.topLeftCorner<3, 3>() = point_covariance;
  joint.bottomRightCorner<6, 6>() = batch.cam_from_world_covariances[static_cast<size_t>(frame)];
  const auto cross = batch.point_cam_from_world_covariances.find({track, frame});
  if (cross != batch.point_cam_from_world_covariances.end()) {
    joint.topRightCorner<3, 6>() = cross->second;
    joint.bottomLeftCorner<6, 3>() = cross->second.transpose();
  }
  return J * joint * J.transpose();
}

mrpt::Clock::time_point timestamp_of(double seconds) { return mrpt::Clock::fromDouble(seconds); }

}  // namespace

double SlamRawlogSummary::quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0;
  const auto index = static_cast<size_t>(std::lround(q * static_cast<double>(sorted.size() - 1)));
  return sorted[std::min(index, sorted.size() - 1)];
}

Eigen::Vector3d spherical_coordinates(const Eigen::Vector3d& p, Eigen::Matrix3d* jacobian) {
  const double horizontal2 = p.x() * p.x() + p.y() * p.y();
  const double horizontal = std::sqrt(horizontal2);
  const double range = p.norm();
  const Eigen::Vector3d rpy(range, horizontal > 0 ? std::atan2(p.y(), p.x()) : 0.0,
                            range > 0 ? -std::asin(p.z() / range) : 0.0);
  if (jacobian) {
    jacobian->setZero();
    if (range > 0) jacobian->row(0) = p.transpose() / range;
    if (horizontal > 0) {
      const double range2 = range * range;
      jacobian->row(1) << -p.y() / horizontal2, p.x() / horizontal2, 0;
      jacobian->row(2) << p.z() * p.x() / (horizontal * range2),
          p.z() * p.y() / (horizontal * range2), -horizontal / range2;
    }
  }
  return rpy;
}

std::vector<BearingRange> bearing_range_measurements(
    const camera::CatadioptricCamera& camera, const sfm::BatchResult& batch, int frame,
    const std::vector<core::TrackObservation>& frame_observations, double pixel_sigma) {
  // In the batch's own coordinates, those of its covariances.
  const Eigen::Isometry3d cam_from_world =
      core::isometry_of(batch.cam_from_world_parameters.at(static_cast<size_t>(frame)));
  const bool pose_uncertain =
      batch.cam_from_world_covariances.size() == batch.cam_from_world_parameters.size();
  std::vector<BearingRange> measurements;
  for (const core::TrackObservation& o : frame_observations) {
    const auto point = batch.points.find(o.track);
    if (point == batch.points.end()) continue;
    Eigen::Vector3d origin, direction;
    if (!camera.unproject(o.pixel, &origin, &direction)) continue;
    const Eigen::Vector3d in_camera = cam_from_world * point->second;
    const double depth = direction.dot(in_camera - origin);
    if (!(depth > 0)) continue;
    const Eigen::Vector3d on_ray = origin + depth * direction;

    BearingRange m;
    m.track = o.track;
    Eigen::Matrix3d d_rpy_d_point;
    const Eigen::Vector3d rpy = spherical_coordinates(on_ray, &d_rpy_d_point);
    m.range = rpy[0];
    m.yaw = rpy[1];
    m.pitch = rpy[2];
    // The pixel's noise moves the ray at a given depth; the point's uncertainty moves the depth.
    Eigen::Matrix<double, 3, 2> d_rpy_d_pixel;
    bool differentiable = true;
    for (int axis = 0; axis < 2 && differentiable; ++axis) {
      Eigen::Vector2d step = Eigen::Vector2d::Zero();
      step[axis] = kPixelStep;
      Eigen::Vector3d plus, minus;
      differentiable = point_on_ray(camera, o.pixel + step, depth, &plus) &&
                       point_on_ray(camera, o.pixel - step, depth, &minus);
      if (!differentiable) break;
      Eigen::Vector3d difference = spherical_coordinates(plus) - spherical_coordinates(minus);
      difference[1] = std::remainder(difference[1], 2 * M_PI);
      d_rpy_d_pixel.col(axis) = difference / (2 * kPixelStep);
    }
    if (!differentiable) continue;
    m.covariance = pixel_sigma * pixel_sigma * d_rpy_d_pixel * d_rpy_d_pixel.transpose();
    const auto point_covariance = batch.point_covariances.find(o.track);
    if (point_covariance != batch.point_covariances.end()) {
      const double depth_variance =
          direction.dot(point_in_camera_covariance(batch, frame, o.track, point->second,
                                                   point_covariance->second, pose_uncertain) *
                        direction);
      const Eigen::Vector3d d_rpy_d_depth = d_rpy_d_point * direction;
      m.covariance += depth_variance * d_rpy_d_depth * d_rpy_d_depth.transpose();
    }
    measurements.push_back(m);
  }
  return measurements;
}

SlamRawlogSummary write_slam_rawlog(const std::string& path,
                                    const camera::CatadioptricCamera& camera,
                                    const std::vector<core::TrackObservation>& observations,
                                    const sfm::BatchResult& batch,
                                    const std::vector<double>& frame_times,
                                    const Eigen::Isometry3d& body_from_cam, double pixel_sigma) {
  const size_t frames = batch.world_from_cam.size();
  if (frame_times.size() != frames)
    throw std::invalid_argument("write_slam_rawlog: " + std::to_string(frame_times.size()) +
                                " frame times for " + std::to_string(frames) + " frames");
  const std::vector<PoseGraphEdge> increments = consecutive_edges(batch, body_from_cam);
  std::vector<std::vector<core::TrackObservation>> by_frame(frames);
  for (const core::TrackObservation& o : observations)
    if (o.frame >= 0 && static_cast<size_t>(o.frame) < frames) by_frame[o.frame].push_back(o);

  std::vector<std::vector<BearingRange>> measured(frames);
  SlamRawlogSummary summary;
  summary.frames = static_cast<int>(frames);
  for (size_t f = 0; f < frames; ++f) {
    measured[f] = bearing_range_measurements(camera, batch, static_cast<int>(f), by_frame[f],
                                             pixel_sigma);
    for (const BearingRange& m : measured[f]) {
      summary.range_sigmas.push_back(std::sqrt(m.covariance(0, 0)));
      summary.yaw_sigmas.push_back(std::sqrt(m.covariance(1, 1)));
      summary.pitch_sigmas.push_back(std::sqrt(m.covariance(2, 2)));
    }
    summary.measurements += static_cast<long>(measured[f].size());
  }
  for (auto* sigmas : {&summary.range_sigmas, &summary.yaw_sigmas, &summary.pitch_sigmas})
    std::sort(sigmas->begin(), sigmas->end());

  const mrpt::poses::CPose3D camera_on_robot = pose_of(body_from_cam);
  io::write_atomically(path, [&](const std::string& temporary_path) {
    mrpt::io::CFileGZOutputStream file;
    if (!file.open(temporary_path)) throw std::runtime_error(path + ": cannot write");
    auto archive = mrpt::serialization::archiveFrom(file);
    for (size_t f = 0; f < frames; ++f) {
      const auto time = timestamp_of(frame_times[f]);
      mrpt::obs::CActionRobotMovement3D movement;
      movement.timestamp = time;
      movement.estimationMethod = mrpt::obs::CActionRobotMovement3D::emVisualOdometry;
      if (f > 0) {
        const PoseGraphEdge& increment = increments[f - 1];
        movement.poseChange.mean = pose_of(increment.relative);
        movement.poseChange.cov = mrpt::math::CMatrixDouble66(increment.covariance);
      }
      mrpt::obs::CActionCollection actions;
      actions.insert(movement);
      archive << actions;

      auto landmarks = std::make_shared<mrpt::obs::CObservationBearingRange>();
      landmarks->sensorLabel = kLandmarksLabel;
      landmarks->timestamp = time;
      landmarks->sensorLocationOnRobot = camera_on_robot;
      landmarks->fieldOfView_yaw = static_cast<float>(2 * M_PI);
      landmarks->fieldOfView_pitch = static_cast<float>(M_PI);
      landmarks->validCovariances = true;
      landmarks->sensor_std_range =
          static_cast<float>(SlamRawlogSummary::quantile(summary.range_sigmas, 0.95));
      landmarks->sensor_std_yaw =
          static_cast<float>(SlamRawlogSummary::quantile(summary.yaw_sigmas, 0.95));
      landmarks->sensor_std_pitch =
          static_cast<float>(SlamRawlogSummary::quantile(summary.pitch_sigmas, 0.95));
      for (const BearingRange& m : measured[f]) {
        mrpt::obs::CObservationBearingRange::TMeasurement measurement;
        measurement.range = static_cast<float>(m.range);
        measurement.yaw = static_cast<float>(m.yaw);
        measurement.pitch = static_cast<float>(m.pitch);
        measurement.landmarkID = m.track;
        measurement.covariance = mrpt::math::CMatrixDouble33(m.covariance);
        landmarks->sensedData.push_back(measurement);
      }
      mrpt::obs::CSensoryFrame frame;
      frame.insert(landmarks);
      archive << frame;
    }
    file.close();
  });
  return summary;
}

}  // namespace omnisfm::mrpt_plugin
