#pragma once
// MRPT's dead-reckoning and GPS observations turned into sfm::MotionSensors, one object at a
// time, as a rawlog replay or an MRPT application delivers them:
//   - mrpt::obs::CObservationOdometry: the odometry pose (x, y, phi) as it stands;
//   - mrpt::obs::CActionRobotMovement2D (sensory-frame rawlogs): increments composed from a zero
//     pose at the first timestamp seen (an action without a timestamp takes that of the
//     observations after it);
//   - mrpt::obs::CObservationIMU with the three angular rates, turned from the sensor's frame
//     (its sensorPose) into the body's;
//   - mrpt::obs::CObservationGPS with a valid NMEA GGA fix: into the local ENU frame about the
//     configured origin, or about the first fix (GeographicLib's LocalCartesian); the height is
//     GGA's altitude plus the geoid separation, the height above the ellipsoid. The noise comes
//     from the fix quality, HDOP and (from a GSA message) VDOP, see gps_fix_quality.h; the
//     antenna's place on the robot from its sensorPose.
// Odometry comes from one kind only, the first seen (a rawlog holding both would count the motion
// twice); its yaw is unwrapped, continuous across +-pi. Labels filter each kind when not empty.
// Readings are kept in time order: one earlier than the last of its kind is dropped and counted,
// unless the last stands far ahead of it and of the one before (ten times their step): that one,
// misdated, is dropped instead.
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/obs/CAction.h>
#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <optional>
#include <string>

#include "omnisfm/mrpt_plugin/local_enu_frame.h"
#include "omnisfm/sfm/motion_sensors.h"

namespace omnisfm::mrpt_plugin {

struct MotionSensorLabels {
  std::string odometry, gyro, gps;  // empty: any sensor of the kind
};

class MotionSensorCollector {
 public:
  // `gps_origin`: the ENU frame's origin; without one, the first fix's position.
  MotionSensorCollector(const MotionSensorLabels& labels,
                        const std::optional<GeodeticPoint>& gps_origin);

  // Returns whether the observation was a motion sensor's reading that was used.
  bool add(const mrpt::obs::CObservation& observation);
  bool add(const mrpt::obs::CAction& action);

  // Drops what a live estimator no longer needs once it has processed a frame at `timestamp`:
  // odometry and gyro readings before the last one at or before it (that one still bounds the
  // next increment), GPS fixes before it.
  void forget_before(double timestamp);

  // Noise models and body_from_cam are the caller's to set.
  sfm::MotionSensors& sensors() { return sensors_; }
  const sfm::MotionSensors& sensors() const { return sensors_; }
  // The ENU origin in use: the configured one, the first fix's, or none yet.
  const std::optional<LocalEnuFrame>& enu_frame() const { return enu_; }
  // Readings dropped for coming back in time, or dated far ahead of their neighbours.
  std::size_t out_of_order() const { return out_of_order_; }

 private:
  enum class OdometrySource { kNone, kObservations, kActions };
  bool add_odometry(double timestamp, Eigen::Vector3d pose);
  bool add_gyro(const mrpt::obs::CObservation& observation, double timestamp);
  bool add_gps(const mrpt::obs::CObservation& observation, double timestamp);
  void note_time(double timestamp);

  MotionSensorLabels labels_;
  std::optional<LocalEnuFrame> enu_;
  sfm::MotionSensors sensors_;
  OdometrySource odometry_source_ = OdometrySource::kNone;
  std::optional<double> first_time_;
  // CActionRobotMovement2D: the composed pose, and increments waiting for a timestamp.
  Eigen::Vector3d action_pose_{0, 0, 0};
  bool action_pose_pending_ = false;
  std::size_t out_of_order_ = 0;
};

}  // namespace omnisfm::mrpt_plugin
