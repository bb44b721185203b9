#include "run_settings.h"

#include <cmath>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/sfm/settings_file.h"

namespace omnisfm::app {
namespace {

mrpt_plugin::ReplayVision vision_of(const io::IniSection& s) {
  const std::string v = s.get_string("vision", "auto");
  if (v == "auto") return mrpt_plugin::ReplayVision::kAuto;
  if (v == "tracks") return mrpt_plugin::ReplayVision::kTrackedFeatures;
  if (v == "images") return mrpt_plugin::ReplayVision::kImages;
  s.fail("vision", "must be auto, tracks or images");
}

void read_run_section(const io::IniSection& s, RunSettings* settings) {
  mrpt_plugin::ReplayOptions& r = settings->replay;
  r.vision = vision_of(s);
  r.camera_label = s.get_string("camera_label", "");
  r.odometry_label = s.get_string("odometry_label", "");
  r.gyro_label = s.get_string("gyro_label", "");
  r.gps_label = s.get_string("gps_label", "");
  if (s.has("gps_origin")) {
    const std::vector<double> origin = s.get_doubles("gps_origin");
    if (origin.size() != 3 || !(std::abs(origin[0]) <= 90) || !(std::abs(origin[1]) <= 360))
      s.fail("gps_origin", "must be latitude (-90..90), longitude (degrees) and height (m)");
    r.gps_origin = mrpt_plugin::GeodeticPoint{origin[0], origin[1], origin[2]};
  }
  sfm::OdometryNoise& o = settings->odometry_noise;
  o.position_sigma = s.get_positive("odometry_position_sigma", o.position_sigma);
  o.heading_sigma = s.get_positive("odometry_heading_sigma", o.heading_sigma);
  settings->odometry_scale = s.get_positive("odometry_scale", settings->odometry_scale);
  o.scale_sigma = s.get_positive("odometry_scale_sigma", o.scale_sigma, true);
  sfm::GyroNoise& g = settings->gyro_noise;
  g.noise_density = s.get_positive("gyro_noise_density", g.noise_density);
  g.bias_sigma = s.get_positive("gyro_bias_sigma", g.bias_sigma);
  g.bias_walk = s.get_positive("gyro_bias_walk", g.bias_walk);
  r.tracker.max_tracks = s.get_positive_int("max_tracks", r.tracker.max_tracks);
  r.tracker.min_ncc = s.get_positive("min_ncc", r.tracker.min_ncc);
  if (r.tracker.min_ncc > 1) s.fail("min_ncc", "must be at most 1");
  for (const auto& entry : s.unread()) s.fail(entry.key, "unknown key in [run]");
}

}  // namespace

RunSettings read_run_settings(const std::string& path) {
  RunSettings settings;
  if (path.empty()) return settings;
  const io::IniFile ini = io::IniFile::read(path);
  for (const io::IniSection& section : ini.sections()) {
    if (section.name() == "run") {
      read_run_section(section, &settings);
    } else if (section.name() == "sfm") {
      settings.sfm = sfm::read_sfm_settings(section);
    } else if (!(section.name().empty() && section.entries().empty())) {
      if (section.name().empty())
        section.fail(section.entries().front().key, "belongs in the [run] or [sfm] section");
      throw io::InputError(path, section.line(),
                           "unknown section [" + section.name() + "]: expected [run] or [sfm]");
    }
  }
  return settings;
}

}  // namespace omnisfm::app
