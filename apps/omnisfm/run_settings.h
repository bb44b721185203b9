#pragma once
// `omnisfm run --config run.ini`: the estimators' [sfm] section (sfm/settings_file.h) and a [run]
// section for the replay; absent keys keep their defaults:
//   [run]
//   vision = auto               # auto | tracks | images: the rawlog's tracked features, or its
//                               # images through the tracker (auto: tracks when there are any)
//   camera_label =              # sensor labels to use; empty: any
//   odometry_label =  gyro_label =  gps_label =
//   gps_origin = LAT LON HEIGHT # the local ENU frame's origin (degrees, metres above the
//                               # ellipsoid); default: the first GPS fix
//   odometry_position_sigma = 0.01   # m per sqrt(m travelled)
//   odometry_heading_sigma = 0.01    # rad per sqrt(m travelled)
//   odometry_scale = 1               # true distance per distance the wheels read: the
//                                    # "odometry scale" a run with GPS reports
//   odometry_scale_sigma = 0.02      # its relative uncertainty; 0 holds it
//   gyro_noise_density = 2e-4        # rad/s per sqrt(Hz)
//   gyro_bias_sigma = 5e-3           # rad/s
//   gyro_bias_walk = 2e-5            # rad/s^2 per sqrt(Hz)
//   max_tracks = 112  min_ncc = 0.97 # the tracker, for images
// Other sections are errors (a misspelt [sfm] would otherwise be silently ignored).

#include <string>

#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::app {

struct RunSettings {
  sfm::SfmSettings sfm;
  mrpt_plugin::ReplayOptions replay;
  sfm::OdometryNoise odometry_noise;
  double odometry_scale = 1;
  sfm::GyroNoise gyro_noise;
};

// Defaults for an empty path. Throws io::InputError naming the file, the key and its line.
RunSettings read_run_settings(const std::string& path);

}  // namespace omnisfm::app
