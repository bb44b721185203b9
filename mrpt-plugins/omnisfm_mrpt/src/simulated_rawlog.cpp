#include "omnisfm/mrpt_plugin/simulated_rawlog.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/mrpt_plugin/gps_fix_quality.h"
#include "omnisfm/mrpt_plugin/local_enu_frame.h"
#include "omnisfm/mrpt_plugin/observation_camera_model.h"
#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

#include "eigen_poses.h"

namespace omnisfm::mrpt_plugin {
namespace {

// What happens at one instant; at equal times the order below, as sensors would be polled.
enum class EventKind { kOdometry, kGyro, kGps, kFrame };

struct Event {
  double time = 0;
  EventKind kind = EventKind::kFrame;
  std::size_t index = 0;  // into the odometry, the gyro readings or the frames
};

std::vector<Event> time_ordered(const sim::Dataset& d, const sim::DeadReckoning& dr,
                                const sim::GpsTrack& gps) {
  std::vector<Event> events;
  for (std::size_t i = 0; i < gps.fixes.size(); ++i)
    events.push_back({gps.fixes[i].timestamp, EventKind::kGps, i});
  for (std::size_t i = 0; i < dr.odometry.size(); ++i)
    events.push_back({dr.odometry[i].timestamp, EventKind::kOdometry, i});
  for (std::size_t i = 0; i < dr.gyro.size(); ++i)
    events.push_back({dr.gyro[i].timestamp, EventKind::kGyro, i});
  for (std::size_t i = 0; i < d.timestamps.size(); ++i)
    events.push_back({d.timestamps[i], EventKind::kFrame, i});
  std::stable_sort(events.begin(), events.end(), [](const Event& a, const Event& b) {
    return a.time < b.time || (a.time == b.time && a.kind < b.kind);
  });
  return events;
}

std::string settings_text(const sim::Dataset& d, const SimulatedRawlogOptions& o,
                          const sim::DeadReckoning& dr, const sim::GpsTrack& gps) {
  const sim::DeadReckoningOptions& s = o.sensors;
  const auto f = [](double x) { return io::format_double(x); };
  std::ostringstream text;
  text << "# Simulated by omnisfm. Its omnidirectional images and tracked features are omnisfm's\n"
       << "# classes: MRPT tools read them with the plugin libomnisfm_mrpt_classes.so, e.g.\n"
       << "#   rawlog-edit -p /path/to/libomnisfm_mrpt_classes.so --info -i dataset.rawlog\n"
       << "[omnisfm_simulation]\n"
       << "scenario = " << d.scenario << "\n"
       << "sensor_seed = " << s.seed << "\n"
       << "start_time = " << f(o.start_time) << "\n"
       << "frames = " << d.timestamps.size() << "\n"
       << "odometry = " << (dr.odometry.empty() ? "none  # the motion is not planar" : "planar")
       << "\n"
       << "odometry_rate_hz = " << f(s.odometry_rate_hz) << "\n"
       << "odometry_scale_error = " << f(s.odometry_scale_error) << "\n"
       << "odometry_yaw_scale_error = " << f(s.odometry_yaw_scale_error) << "\n"
       << "odometry_position_noise = " << f(s.odometry_position_noise) << "  # m/sqrt(m)\n"
       << "odometry_heading_noise = " << f(s.odometry_heading_noise) << "  # rad/sqrt(m)\n"
       << "gyro_rate_hz = " << f(s.gyro_rate_hz) << "\n"
       << "gyro_noise_density = " << f(s.gyro_noise_density) << "  # rad/s/sqrt(Hz)\n"
       << "gyro_bias_sigma = " << f(s.gyro_bias_sigma) << "  # rad/s\n"
       << "gyro_bias_walk = " << f(s.gyro_bias_walk) << "  # rad/s^2/sqrt(Hz)\n"
       << "gyro_bias_at_start = " << f(dr.gyro_bias_at_start.x()) << " "
       << f(dr.gyro_bias_at_start.y()) << " " << f(dr.gyro_bias_at_start.z()) << "  # rad/s\n";
  if (o.gps) {
    const Eigen::Vector3d t = gps.enu_from_world.translation();
    text << "gps_rate_hz = " << f(o.gps->rate_hz) << "\n"
         << "gps_horizontal_sigma = " << f(gps.horizontal_sigma) << "  # m per axis\n"
         << "gps_vertical_sigma = " << f(gps.vertical_sigma) << "  # m\n"
         << "gps_origin = " << f(gps.latitude_deg) << " " << f(gps.longitude_deg) << " "
         << f(gps.height_m) << "  # latitude, longitude (deg), height (m): the ENU origin\n"
         << "gps_world_heading = " << f(o.gps->world_heading)
         << "  # rad from east to the world's x axis\n"
         << "gps_world_origin_enu = " << f(t.x()) << " " << f(t.y()) << " " << f(t.z()) << "\n";
  }
  return text.str();
}

// The dataset's observations grouped by frame (they are sorted by frame).
std::vector<std::vector<TrackedFeature>> features_by_frame(const sim::Dataset& d) {
  std::vector<std::vector<TrackedFeature>> frames(d.timestamps.size());
  for (const sim::TrackObservation& o : d.observations)
    frames.at(static_cast<std::size_t>(o.frame)).push_back({o.track, o.pixel.x(), o.pixel.y()});
  return frames;
}

class RawlogWriter {
 public:
  RawlogWriter(const sim::Dataset& d, const sim::DeadReckoning& dr, const sim::GpsTrack& gps,
               const SimulatedRawlogOptions& options, mrpt::serialization::CArchive& out)
      : d_(d),
        dr_(dr),
        gps_(gps),
        enu_({gps.latitude_deg, gps.longitude_deg, gps.height_m}),
        gps_fix_(gps_fix_quality_of(gps.horizontal_sigma, gps.vertical_sigma)),
        options_(options),
        out_(out),
        features_(features_by_frame(d)),
        camera_pose_(pose_of(dr.body_from_cam)) {}

  void write_all(SimulatedRawlogSummary* summary) {
    mrpt::obs::CObservationComment comment;
    comment.timestamp = time(d_.timestamps.front());
    comment.text = settings_text(d_, options_, dr_, gps_);
    out_ << comment;
    for (const Event& event : time_ordered(d_, dr_, gps_)) {
      switch (event.kind) {
        case EventKind::kOdometry:
          write_odometry(dr_.odometry[event.index]);
          ++summary->odometry;
          break;
        case EventKind::kGyro:
          write_gyro(dr_.gyro[event.index]);
          ++summary->gyro;
          break;
        case EventKind::kGps:
          write_gps(gps_.fixes[event.index]);
          ++summary->gps;
          break;
        case EventKind::kFrame:
          if (options_.image_file) {
            write_image(static_cast<int>(event.index));
            ++summary->images;
          }
          write_features(static_cast<int>(event.index));
          ++summary->tracked_frames;
          break;
      }
    }
  }

 private:
  mrpt::Clock::time_point time(double t) const {
    return mrpt::Clock::fromDouble(options_.start_time + t);
  }

  void write_odometry(const sim::OdometryReading& reading) {
    mrpt::obs::CObservationOdometry odometry;
    odometry.timestamp = time(reading.timestamp);
    odometry.sensorLabel = kOdometryLabel;
    odometry.odometry = mrpt::poses::CPose2D(reading.pose.x(), reading.pose.y(), reading.pose.z());
    odometry.hasVelocities = true;
    odometry.velocityLocal = {reading.velocity.x(), reading.velocity.y(), reading.velocity.z()};
    out_ << odometry;
  }

  void write_gyro(const sim::GyroReading& reading) {
    mrpt::obs::CObservationIMU imu;
    imu.timestamp = time(reading.timestamp);
    imu.sensorLabel = kGyroLabel;
    imu.set(mrpt::obs::IMU_WX, reading.rate.x());
    imu.set(mrpt::obs::IMU_WY, reading.rate.y());
    imu.set(mrpt::obs::IMU_WZ, reading.rate.z());
    out_ << imu;
  }

  void write_gps(const sim::GpsReading& reading) {
    mrpt::obs::CObservationGPS gps;
    gps.timestamp = time(reading.timestamp);
    gps.originalReceivedTimestamp = gps.timestamp;
    gps.has_satellite_timestamp = true;
    gps.sensorLabel = kGpsLabel;
    gps.sensorPose = mrpt::poses::CPose3D(gps_.antenna_in_body.x(), gps_.antenna_in_body.y(),
                                          gps_.antenna_in_body.z(), 0, 0, 0);
    const GeodeticPoint where = enu_.geodetic_of(reading.enu);
    mrpt::obs::gnss::Message_NMEA_GGA gga;
    const double seconds_of_day = std::fmod(options_.start_time + reading.timestamp, 86400.0);
    gga.fields.UTCTime.hour = static_cast<uint8_t>(seconds_of_day / 3600);
    gga.fields.UTCTime.minute = static_cast<uint8_t>(std::fmod(seconds_of_day, 3600) / 60);
    gga.fields.UTCTime.sec = std::fmod(seconds_of_day, 60);
    gga.fields.latitude_degrees = where.latitude_deg;
    gga.fields.longitude_degrees = where.longitude_deg;
    gga.fields.altitude_meters = where.height_m;
    gga.fields.geoidal_distance = 0;
    gga.fields.orthometric_altitude = where.height_m;
    gga.fields.fix_quality = static_cast<uint8_t>(gps_fix_.fix_quality);
    gga.fields.satellitesUsed = static_cast<uint32_t>(gps_fix_.satellites);
    gga.fields.thereis_HDOP = true;
    gga.fields.HDOP = static_cast<float>(gps_fix_.hdop);
    gps.setMsg(gga);
    mrpt::obs::gnss::Message_NMEA_GSA gsa;
    gsa.fields.auto_selection_fix = 'A';
    gsa.fields.fix_2D_3D = '3';
    gsa.fields.HDOP = gps_fix_.hdop;
    gsa.fields.VDOP = gps_fix_.vdop;
    gsa.fields.PDOP = std::hypot(gps_fix_.hdop, gps_fix_.vdop);
    gps.setMsg(gsa);
    out_ << gps;
  }

  // Stock images, so that stock tools show and handle them, after their model (the first frame's).
  void write_image(int frame) {
    const auto timestamp = time(d_.timestamps[static_cast<std::size_t>(frame)]);
    if (frame == 0) {
      CObservationCameraModel model;
      model.timestamp = timestamp;
      model.sensorLabel = kOmniCameraLabel;
      model.sensorPose = camera_pose_;
      model.model.set_camera(d_.camera);
      out_ << model;
    }
    const std::string file = options_.image_file(frame);
    mrpt::obs::CObservationImage image;
    image.timestamp = timestamp;
    image.sensorLabel = kOmniCameraLabel;
    image.cameraPose = camera_pose_;
    image.cameraParams = inner_camera_params(d_.camera);
    if (!image.image.loadFromFile(file, 0))
      throw std::runtime_error(file + ": cannot read the image of frame " + std::to_string(frame));
    out_ << image;
  }

  void write_features(int frame) {
    CObservationTrackedFeatures features;
    features.timestamp = time(d_.timestamps[static_cast<std::size_t>(frame)]);
    features.sensorLabel = kTrackedFeaturesLabel;
    features.frame = frame;
    features.sensorPose = camera_pose_;
    features.model.set_camera(d_.camera);
    features.features = features_[static_cast<std::size_t>(frame)];
    out_ << features;
  }

  const sim::Dataset& d_;
  const sim::DeadReckoning& dr_;
  const sim::GpsTrack& gps_;
  LocalEnuFrame enu_;
  GpsFixQuality gps_fix_;
  const SimulatedRawlogOptions& options_;
  mrpt::serialization::CArchive& out_;
  std::vector<std::vector<TrackedFeature>> features_;
  mrpt::poses::CPose3D camera_pose_;
};

}  // namespace

SimulatedRawlogSummary write_simulated_rawlog(const sim::Dataset& dataset, const std::string& path,
                                              const SimulatedRawlogOptions& options) {
  const sim::DeadReckoning dead_reckoning = sim::simulate_dead_reckoning(dataset, options.sensors);
  SimulatedRawlogSummary summary;
  if (options.gps) summary.gps_track = sim::simulate_gps(dataset, *options.gps);
  const sim::GpsTrack& gps = summary.gps_track;
  io::write_atomically(path, [&](const std::string& temporary_path) {
    mrpt::io::CFileGZOutputStream file;
    if (!file.open(temporary_path)) throw std::runtime_error(path + ": cannot write");
    auto archive = mrpt::serialization::archiveFrom(file);
    RawlogWriter(dataset, dead_reckoning, gps, options, archive).write_all(&summary);
    file.close();
  });
  return summary;
}

}  // namespace omnisfm::mrpt_plugin
