#pragma once
// A simulated dataset as an MRPT rawlog in the observation format (MRPT 2's preferred one: a
// time-ordered sequence of CObservation objects, gzip-compressed as MRPT's tools write it):
//   - first, a CObservationComment with the simulation's settings and the sensors' true errors
//     (an INI section [omnisfm_simulation]), for whoever checks an estimator against them;
//   - per frame, a CObservationTrackedFeatures (label OMNI_TRACKS, carrying the camera model)
//     and, when image files are given, a stock mrpt::obs::CObservationImage (label OMNI_CAMERA),
//     whose model a CObservationCameraModel of the same label carries, written once before the
//     first image (stock tools show and externalise stock images only);
//   - wheel odometry, mrpt::obs::CObservationOdometry (label ODOMETRY), for planar motion only;
//   - a gyro, mrpt::obs::CObservationIMU (label IMU) with the angular rates only,
// from sim::simulate_dead_reckoning (its header states the sensor models);
//   - with `gps` (an outdoor variant), a GPS receiver, mrpt::obs::CObservationGPS (label GPS)
//     holding NMEA GGA (latitude, longitude, height above the ellipsoid with a geoid separation of
//     0, fix quality, satellites, HDOP) and GSA (VDOP) messages, from sim::simulate_gps, turned
//     into geodetic coordinates about its origin; fix quality and dilutions state the receiver's
//     noise (gps_fix_quality.h). Its sensorPose is the antenna on the robot. Cameras sit on the
// robot at body_from_cam, the IMU at the robot's origin. A timestamp is start_time plus the
// dataset's time (MRPT reserves time 0 for "no timestamp").
//
// MRPT-free: the omnisfm command calls this without MRPT headers.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

#include "omnisfm/sim/dataset.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/gps_receiver.h"

namespace omnisfm::mrpt_plugin {

inline constexpr const char* kOmniCameraLabel = "OMNI_CAMERA";
inline constexpr const char* kTrackedFeaturesLabel = "OMNI_TRACKS";
inline constexpr const char* kOdometryLabel = "ODOMETRY";
inline constexpr const char* kGyroLabel = "IMU";
inline constexpr const char* kGpsLabel = "GPS";

struct SimulatedRawlogOptions {
  sim::DeadReckoningOptions sensors;
  double start_time = 1e9;  // seconds since the Unix epoch at the dataset's time 0
  // The image file (PNG, or any format OpenCV reads) of each frame; null for tracks only.
  std::function<std::string(int frame)> image_file;
  std::optional<sim::GpsOptions> gps;  // none indoors
};

struct SimulatedRawlogSummary {
  std::size_t images = 0, tracked_frames = 0, odometry = 0, gyro = 0, gps = 0;
  sim::GpsTrack gps_track;  // the fixes written and their ground truth (empty without GPS)
};

// Writes the rawlog to `path`, replaced whole or not at all. Throws std::runtime_error naming the
// file when it cannot be written or an image file cannot be read, and std::invalid_argument for
// what sim::simulate_dead_reckoning and sim::simulate_gps reject.
SimulatedRawlogSummary write_simulated_rawlog(const sim::Dataset& dataset, const std::string& path,
                                              const SimulatedRawlogOptions& options);

}  // namespace omnisfm::mrpt_plugin
