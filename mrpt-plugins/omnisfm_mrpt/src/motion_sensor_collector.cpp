#include "omnisfm/mrpt_plugin/motion_sensor_collector.h"

#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>

#include "omnisfm/mrpt_plugin/gps_fix_quality.h"

namespace omnisfm::mrpt_plugin {
namespace {

bool labelled(const std::string& wanted, const std::string& label) {
  return wanted.empty() || wanted == label;
}

// `to` moved by whole turns to lie within pi of `from`.
double unwrapped(double from, double to) {
  return to - 2 * M_PI * std::round((to - from) / (2 * M_PI));
}

// Whether a reading at `timestamp` may join `samples` in time order. One earlier than the last is
// dropped, unless the last stands far ahead of both: beyond kAheadFactor times the new one's
// step from the reading before the last. Then the last is taken as misdated (a single reading
// dated ahead would otherwise hold its predecessor's rate over every later frame and refuse every
// later reading) and dropped instead. A reading merely late, or two swapped, keeps the earlier
// order. Either way one reading counts in `dropped`.
template <typename T>
bool make_room_in_time_order(std::vector<T>* samples, double timestamp, std::size_t* dropped) {
  constexpr double kAheadFactor = 10;
  if (samples->empty() || timestamp >= samples->back().timestamp) return true;
  ++*dropped;
  if (samples->size() < 2) return false;
  const double before = (*samples)[samples->size() - 2].timestamp;
  const double step = timestamp - before;
  if (step < 0 || !(samples->back().timestamp - before > kAheadFactor * step)) return false;
  samples->pop_back();
  return true;
}

// Erases the samples before the last one at or before `timestamp`.
template <typename T>
void keep_from_last_at_or_before(std::vector<T>* samples, double timestamp) {
  const auto after = std::upper_bound(
      samples->begin(), samples->end(), timestamp,
      [](double time, const T& sample) { return time < sample.timestamp; });
  if (after - samples->begin() > 1) samples->erase(samples->begin(), after - 1);
}

// A movement action's increment as the planar wheel model takes it (x, y, yaw); none for other
// actions and for a 2D movement without its pose change.
std::optional<mrpt::poses::CPose2D> planar_increment(const mrpt::obs::CAction& action) {
  if (const auto* planar = dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(&action)) {
    if (!planar->poseChange) return std::nullopt;
    return planar->poseChange->getMeanVal();
  }
  if (const auto* spatial = dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(&action)) {
    const mrpt::poses::CPose3D& d = spatial->poseChange.mean;
    return mrpt::poses::CPose2D(d.x(), d.y(), d.yaw());
  }
  return std::nullopt;
}

}  // namespace

void MotionSensorCollector::forget_before(double timestamp) {
  keep_from_last_at_or_before(&sensors_.odometry, timestamp);
  keep_from_last_at_or_before(&sensors_.gyro, timestamp);
  auto& gps = sensors_.gps;
  gps.erase(gps.begin(), std::find_if(gps.begin(), gps.end(), [&](const sfm::GpsSample& fix) {
              return fix.timestamp >= timestamp;
            }));
}

MotionSensorCollector::MotionSensorCollector(const MotionSensorLabels& labels,
                                             const std::optional<GeodeticPoint>& gps_origin)
    : labels_(labels) {
  if (gps_origin) enu_.emplace(*gps_origin);
}

void MotionSensorCollector::note_time(double timestamp) {
  if (!first_time_) first_time_ = timestamp;
  if (action_pose_pending_) {
    action_pose_pending_ = false;
    add_odometry(timestamp, action_pose_);
  }
}

bool MotionSensorCollector::add_odometry(double timestamp, Eigen::Vector3d pose) {
  std::vector<sfm::OdometrySample>& odometry = sensors_.odometry;
  if (!make_room_in_time_order(&odometry, timestamp, &out_of_order_)) return false;
  if (!odometry.empty()) pose.z() = unwrapped(odometry.back().pose.z(), pose.z());
  odometry.push_back({timestamp, pose});
  return true;
}

bool MotionSensorCollector::add(const mrpt::obs::CObservation& observation) {
  if (observation.timestamp == INVALID_TIMESTAMP) return false;
  const double t = mrpt::Clock::toDouble(observation.timestamp);
  note_time(t);
  if (const auto* odometry = dynamic_cast<const mrpt::obs::CObservationOdometry*>(&observation)) {
    if (!labelled(labels_.odometry, observation.sensorLabel) ||
        odometry_source_ == OdometrySource::kActions)
      return false;
    odometry_source_ = OdometrySource::kObservations;
    return add_odometry(
        t, Eigen::Vector3d(odometry->odometry.x(), odometry->odometry.y(), odometry->odometry.phi()));
  }
  if (dynamic_cast<const mrpt::obs::CObservationIMU*>(&observation))
    return labelled(labels_.gyro, observation.sensorLabel) && add_gyro(observation, t);
  if (dynamic_cast<const mrpt::obs::CObservationGPS*>(&observation))
    return labelled(labels_.gps, observation.sensorLabel) && add_gps(observation, t);
  return false;
}

bool MotionSensorCollector::add(const mrpt::obs::CAction& action) {
  const std::optional<mrpt::poses::CPose2D> increment = planar_increment(action);
  if (!increment || odometry_source_ == OdometrySource::kObservations) return false;
  odometry_source_ = OdometrySource::kActions;
  const bool timed = action.timestamp != INVALID_TIMESTAMP;
  const double t = timed ? mrpt::Clock::toDouble(action.timestamp) : 0;
  // The odometry starts at zero where the log starts (or at this first movement).
  if (sensors_.odometry.empty() && !action_pose_pending_)
    add_odometry(first_time_ ? *first_time_ : (timed ? t : 0), Eigen::Vector3d::Zero());
  const mrpt::poses::CPose2D composed =
      mrpt::poses::CPose2D(action_pose_.x(), action_pose_.y(), action_pose_.z()) + *increment;
  action_pose_ = Eigen::Vector3d(composed.x(), composed.y(), composed.phi());
  if (!timed) {
    action_pose_pending_ = true;
    return true;
  }
  note_time(t);
  return add_odometry(t, action_pose_);
}

bool MotionSensorCollector::add_gyro(const mrpt::obs::CObservation& observation,
                                     double timestamp) {
  const auto& imu = dynamic_cast<const mrpt::obs::CObservationIMU&>(observation);
  if (!imu.has(mrpt::obs::IMU_WX) || !imu.has(mrpt::obs::IMU_WY) || !imu.has(mrpt::obs::IMU_WZ))
    return false;
  if (!make_room_in_time_order(&sensors_.gyro, timestamp, &out_of_order_)) return false;
  const Eigen::Vector3d rate_in_sensor(imu.get(mrpt::obs::IMU_WX), imu.get(mrpt::obs::IMU_WY),
                                       imu.get(mrpt::obs::IMU_WZ));
  const Eigen::Matrix3d body_from_sensor = imu.sensorPose.getRotationMatrix().asEigen();
  sensors_.gyro.push_back({timestamp, body_from_sensor * rate_in_sensor});
  return true;
}

bool MotionSensorCollector::add_gps(const mrpt::obs::CObservation& observation,
                                    double timestamp) {
  const auto& gps = dynamic_cast<const mrpt::obs::CObservationGPS&>(observation);
  // (MRPT 2.5's const getMsgByClassPtr does not compile: ask first, then get.)
  if (!gps.hasMsgClass<mrpt::obs::gnss::Message_NMEA_GGA>()) return false;
  const auto* gga = &gps.getMsgByClass<mrpt::obs::gnss::Message_NMEA_GGA>();
  if (gga->fields.fix_quality == 0) return false;
  if (!make_room_in_time_order(&sensors_.gps, timestamp, &out_of_order_)) return false;
  const GeodeticPoint where{gga->fields.latitude_degrees, gga->fields.longitude_degrees,
                            gga->fields.altitude_meters + gga->fields.geoidal_distance};
  if (!enu_) enu_.emplace(where);
  const auto* gsa = gps.hasMsgClass<mrpt::obs::gnss::Message_NMEA_GSA>()
                        ? &gps.getMsgByClass<mrpt::obs::gnss::Message_NMEA_GSA>()
                        : nullptr;
  const double hdop = gga->fields.thereis_HDOP ? gga->fields.HDOP : (gsa ? gsa->fields.HDOP : 1.0);
  const GpsSigma sigma = gps_sigma_of(gga->fields.fix_quality, hdop, gsa ? gsa->fields.VDOP : 0);
  sensors_.gps.push_back({timestamp, enu_->enu_of(where), sigma.horizontal, sigma.vertical});
  sensors_.antenna_in_body =
      Eigen::Vector3d(gps.sensorPose.x(), gps.sensorPose.y(), gps.sensorPose.z());
  return true;
}

}  // namespace omnisfm::mrpt_plugin
