#pragma once
// The options of a rawlog replay and of OmniSfmEstimator, one set of names for both: the [run]
// section of `omnisfm run --config` and the section OmniSfmEstimatorOptions::loadFromConfigFile
// reads. Absent keys keep their defaults; unknown keys are errors.
//   vision = auto               # auto | tracks | images: the rawlog's tracked features, or its
//                               # images through the tracker (auto: tracks when there are any;
//                               # OmniSfmEstimator takes the first kind it is given)
//   camera_label =              # sensor labels to use; empty: any
//   odometry_label =  gyro_label =  gps_label =
//   gps_origin = LAT LON HEIGHT # the local ENU frame's origin (degrees, metres above the
//                               # ellipsoid); default: the first GPS fix
//   odometry_position_sigma = 0.01   # m per sqrt(m travelled), 1e-6 to 1
//   odometry_heading_sigma = 0.01    # rad per sqrt(m travelled), 1e-6 to 1
//   odometry_scale = 1               # true distance per distance the wheels read, 0.1 to 10:
//                                    # the "odometry scale" a run with GPS reports
//   odometry_scale_sigma = 0.02      # its relative uncertainty, up to 0.5; 0 holds it
//   gyro_noise_density = 2e-4        # rad/s per sqrt(Hz), 1e-10 to 1
//   gyro_bias_sigma = 5e-3           # rad/s, 1e-10 to 1
//   gyro_bias_walk = 2e-5            # rad/s^2 per sqrt(Hz), 1e-12 to 1
//   max_tracks = 112  min_ncc = 0.97 # the tracker, for images
//   keyframe_distance_m = 1          # OmniSfmEstimator's keyframes: one each time the robot has
//   keyframe_angle_deg = 10          # moved or turned this much (omnisfm run keeps none)

#include <cmath>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/sfm/motion_sensors.h"

namespace omnisfm::mrpt_plugin {

struct RunOptions {
  ReplayOptions replay;
  sfm::OdometryNoise odometry_noise;
  double odometry_scale = 1;
  sfm::GyroNoise gyro_noise;
  double keyframe_distance_m = 1.0;
  double keyframe_angle_rad = 10 * M_PI / 180;
};

// Reads the keys above from `section` into *options (the camera stays as it is). Throws
// io::InputError naming the file, the key and its line for an unknown key or a bad value.
void read_run_options(const io::IniSection& section, RunOptions* options);

// The keys above at the values of `options`, for writing back (gps_origin only when set).
io::IniSection run_options_section(const RunOptions& options, const std::string& name);

}  // namespace omnisfm::mrpt_plugin
