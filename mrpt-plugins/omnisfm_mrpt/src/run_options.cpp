#include "omnisfm/mrpt_plugin/run_options.h"

#include <cmath>

#include "omnisfm/io/number_text.h"
#include "omnisfm/sfm/sensor_ranges.h"

namespace omnisfm::mrpt_plugin {
namespace {

ReplayVision vision_of(const io::IniSection& s, ReplayVision current) {
  if (!s.has("vision")) return current;
  const std::string v = s.get_string("vision");
  if (v == "auto") return ReplayVision::kAuto;
  if (v == "tracks") return ReplayVision::kTrackedFeatures;
  if (v == "images") return ReplayVision::kImages;
  s.fail("vision", "must be auto, tracks or images");
}

const char* vision_name(ReplayVision vision) {
  switch (vision) {
    case ReplayVision::kTrackedFeatures:
      return "tracks";
    case ReplayVision::kImages:
      return "images";
    default:
      return "auto";
  }
}

}  // namespace

void read_run_options(const io::IniSection& s, RunOptions* options) {
  ReplayOptions& r = options->replay;
  r.vision = vision_of(s, r.vision);
  r.camera_label = s.get_string("camera_label", r.camera_label);
  r.odometry_label = s.get_string("odometry_label", r.odometry_label);
  r.gyro_label = s.get_string("gyro_label", r.gyro_label);
  r.gps_label = s.get_string("gps_label", r.gps_label);
  if (s.has("gps_origin")) {
    const std::vector<double> origin = s.get_doubles("gps_origin");
    if (origin.size() != 3 || !(std::abs(origin[0]) <= 90) || !(std::abs(origin[1]) <= 360) ||
        !std::isfinite(origin[2]))
      s.fail("gps_origin", "must be latitude (-90..90), longitude (degrees) and height (m)");
    r.gps_origin = GeodeticPoint{origin[0], origin[1], origin[2]};
  }
  // The bounds hold what a sensor's setting can mean (sfm/sensor_ranges.h).
  sfm::MotionSensors sensors;
  sensors.odometry_noise = options->odometry_noise;
  sensors.odometry_scale = options->odometry_scale;
  sensors.gyro_noise = options->gyro_noise;
  for (const sfm::SensorRange& range : sfm::sensor_ranges()) {
    double& field = range.field(sensors);
    field = s.get_within(range.key, field, range.low, range.high, range.meaning);
  }
  options->odometry_noise = sensors.odometry_noise;
  options->odometry_scale = sensors.odometry_scale;
  options->gyro_noise = sensors.gyro_noise;
  r.tracker.max_tracks = s.get_positive_int("max_tracks", r.tracker.max_tracks);
  // As track's --max-tracks: the filter starts from 6 tracks.
  if (r.tracker.max_tracks < 6 || r.tracker.max_tracks > 100000)
    s.fail("max_tracks", "must be a whole number from 6 to 100000");
  r.tracker.min_ncc = s.get_positive("min_ncc", r.tracker.min_ncc);
  // A correlation of 1 is never reached: every track would end at once.
  if (!(r.tracker.min_ncc < 1)) s.fail("min_ncc", "must be below 1");
  options->keyframe_distance_m =
      s.get_positive("keyframe_distance_m", options->keyframe_distance_m, true);
  options->keyframe_angle_rad =
      s.get_positive("keyframe_angle_deg", options->keyframe_angle_rad * 180 / M_PI, true) *
      M_PI / 180;
  for (const auto& entry : s.unread())
    s.fail(entry.key, "unknown key in [" + s.name() + "]");
}

io::IniSection run_options_section(const RunOptions& options, const std::string& name) {
  io::IniSection s("", name, 0);
  const auto number = [](double x) { return io::format_double(x); };
  const ReplayOptions& r = options.replay;
  s.set("vision", vision_name(r.vision));
  s.set("camera_label", r.camera_label);
  s.set("odometry_label", r.odometry_label);
  s.set("gyro_label", r.gyro_label);
  s.set("gps_label", r.gps_label);
  if (r.gps_origin)
    s.set("gps_origin", number(r.gps_origin->latitude_deg) + " " +
                            number(r.gps_origin->longitude_deg) + " " +
                            number(r.gps_origin->height_m));
  s.set("odometry_position_sigma", number(options.odometry_noise.position_sigma));
  s.set("odometry_heading_sigma", number(options.odometry_noise.heading_sigma));
  s.set("odometry_scale", number(options.odometry_scale));
  s.set("odometry_scale_sigma", number(options.odometry_noise.scale_sigma));
  s.set("gyro_noise_density", number(options.gyro_noise.noise_density));
  s.set("gyro_bias_sigma", number(options.gyro_noise.bias_sigma));
  s.set("gyro_bias_walk", number(options.gyro_noise.bias_walk));
  s.set("max_tracks", std::to_string(r.tracker.max_tracks));
  s.set("min_ncc", number(r.tracker.min_ncc));
  s.set("keyframe_distance_m", number(options.keyframe_distance_m));
  s.set("keyframe_angle_deg", number(options.keyframe_angle_rad * 180 / M_PI));
  return s;
}

}  // namespace omnisfm::mrpt_plugin
