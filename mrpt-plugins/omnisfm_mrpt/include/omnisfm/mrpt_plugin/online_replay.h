#pragma once
// A rawlog replayed through the online estimator (omni_sfm_estimator.h) one object at a time, in
// constant memory, for `[sfm] batch = false` on rawlogs of any length: the camera's tracked
// features, or its images through the tracker, the filter propagated by the wheel odometry and
// the gyro (GPS fixes need the batch and are only counted). MRPT-free, like rawlog_replay_input.h.
//
// Vision: as ReplayVision says, except that kAuto takes the first kind of camera observation met
// (a single pass cannot look ahead for tracked features). Damage: the replay stops at the first
// damaged object, everything before it used, and `read` names it.

#include <cmath>
#include <cstddef>
#include <functional>
#include <string>

#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/sfm/online_filter.h"

namespace omnisfm::mrpt_plugin {

struct OnlineReplaySettings {
  ReplayOptions replay;
  sfm::FilterSettings filter;
  sfm::OdometryNoise odometry_noise;
  sfm::GyroNoise gyro_noise;
  double odometry_scale = 1;  // true distance per distance the wheels read
};

struct OnlineReplaySummary {
  std::string vision;  // "tracked features" or "images"; empty when no camera frame came
  int frames = 0;
  std::size_t odometry = 0, gyro = 0, gps = 0;  // readings met
  RawlogReadResult read;
  // The tracks' noise the filter took at the end (OnlineFilter::pixel_sigma()); NaN with no filter.
  double noise_px = NAN;
};

struct OnlineReplayOutputs {
  // After each camera frame: the filter, the frame's number (from 0) and time (seconds since the
  // Unix epoch).
  std::function<void(const sfm::OnlineFilter&, int frame, double time)> frame;
  sfm::OnlineFilter::PointEnded point_ended;
  sfm::OnlineFilter::TrackRejected track_rejected;
  // After the last object, with the filter when a camera frame started one: what it still holds
  // is to be taken here, since the filter ends with the replay.
  std::function<void(const sfm::OnlineFilter&)> end;
};

// Throws io::InputError when the file cannot be opened, when a camera frame comes without a camera
// (a stock CObservationImage and no settings.replay.camera), and naming the object when its
// images cannot be tracked.
OnlineReplaySummary replay_online(const std::string& path, const OnlineReplaySettings& settings,
                                  const OnlineReplayOutputs& outputs,
                                  const ReplayProgress& progress = nullptr);

}  // namespace omnisfm::mrpt_plugin
