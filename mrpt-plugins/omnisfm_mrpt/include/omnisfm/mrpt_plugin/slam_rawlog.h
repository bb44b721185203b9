#pragma once
// The batch's estimate as a rawlog of stock MRPT classes only, in the sensory-frame format that
// stock SLAM apps read (kf-slam with CRangeBearingKFSLAM in 6D, rbpf-slam, icp-slam), no plugin
// needed. Per camera frame k, in time order:
//   - a CActionCollection holding a CActionRobotMovement3D: the robot's increment from frame
//     k - 1 to k (zero for frame 0), with its covariance over MRPT's x y z yaw pitch roll from
//     the batch's joint covariance of the two poses (consecutive_edges, pose_graph_file.h);
//   - a CSensoryFrame holding a CObservationBearingRange (label OMNI_LANDMARKS) with its
//     sensorLocationOnRobot the camera on the robot: a measurement per track the batch kept
//     (landmarkID the track id), range, yaw and pitch (MRPT's CPose3D::sphericalCoordinates) of
//     the point on the pixel's reflected ray nearest the batch's point. A noncentral camera's ray
//     does not pass through the camera's origin, so the bearing is the point's, not the ray's;
//     it carries the pixel's noise, and the range the batch's uncertainty of the point along
//     the ray as seen from the camera (bearing_range_measurements). Each measurement's 3x3 covariance is set (validCovariances), and sensor_std_* hold
//     their 0.95 quantiles (one noise for all, as kf-slam takes its ini's std_sensor_*: smaller
//     would overweigh the measurements that deserve least).
// The robot is the body frame (x forward, y left, z up); robot_k = world_from_cam_k cam_from_body.
// Tracks the batch did not keep (outliers, too few frames) are left out.
//
// MRPT-free: the omnisfm command calls this without MRPT headers.

#include <Eigen/Geometry>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/sfm/batch_adjustment.h"

namespace omnisfm::mrpt_plugin {

inline constexpr const char* kLandmarksLabel = "OMNI_LANDMARKS";

// One landmark seen from the camera, in MRPT's spherical coordinates about frame C.
struct BearingRange {
  int track = 0;
  double range = 0, yaw = 0, pitch = 0;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // over range, yaw, pitch
};

// MRPT's spherical coordinates (range, yaw, pitch) of a point and their Jacobian.
Eigen::Vector3d spherical_coordinates(const Eigen::Vector3d& point,
                                      Eigen::Matrix3d* jacobian = nullptr);

// The measurements of the observations of `frame` (`frame_observations`, all of that frame) whose
// tracks the batch kept (batch.points), seen from the frame's pose as the batch's parameters hold
// it (batch.cam_from_world_parameters): `pixel_sigma` is the pixels' noise per coordinate. The
// range's uncertainty is the point's as seen from the camera, from the batch's covariances of the
// point, the frame's pose and, with BatchSettings::point_cam_from_world_covariances, the two
// together (without it they are taken as independent, which overstates it where they share the
// scale); without point covariances the range carries only the pixel's noise. Observations whose
// ray does not reach the point (it lies behind the mirror) or whose pixel the camera cannot
// unproject are left out.
std::vector<BearingRange> bearing_range_measurements(
    const camera::CatadioptricCamera& camera, const sfm::BatchResult& batch, int frame,
    const std::vector<core::TrackObservation>& frame_observations, double pixel_sigma);

struct SlamRawlogSummary {
  int frames = 0;
  long measurements = 0;
  // The measurements' standard deviations (m, rad) at a quantile: 0.5 the median. A single
  // sensor noise (kf-slam's std_sensor_*) at the 0.95 quantiles weighs 95 % of the measurements no
  // more than they deserve.
  std::vector<double> range_sigmas, yaw_sigmas, pitch_sigmas;  // sorted
  static double quantile(const std::vector<double>& sorted, double q);
};

// Writes `path` (gzip-compressed, as MRPT writes rawlogs), replaced whole or not at all.
// `observations`: the tracks (any order); `frame_times`: seconds since the Unix epoch, one per
// batch frame; `body_from_cam`: the camera on the robot. Throws std::invalid_argument when the
// batch has no pose covariances or the times do not match its frames, std::runtime_error naming
// `path` when it cannot be written.
SlamRawlogSummary write_slam_rawlog(const std::string& path,
                                    const camera::CatadioptricCamera& camera,
                                    const std::vector<core::TrackObservation>& observations,
                                    const sfm::BatchResult& batch,
                                    const std::vector<double>& frame_times,
                                    const Eigen::Isometry3d& body_from_cam, double pixel_sigma);

}  // namespace omnisfm::mrpt_plugin
