#pragma once
// Everything a replay with fusion takes from an MRPT rawlog, in the estimators' terms (no MRPT
// types, so that the omnisfm command needs no MRPT headers):
//   - the vision: feature tracks and the time of each frame, either the rawlog's own
//     CObservationTrackedFeatures, or its images (CObservationOmniImage with its camera, or a stock
//     CObservationImage with the camera given) through the tracker (libs/track);
//   - the motion sensors (motion_sensor_collector.h states what is read and how), with the
//     camera's place on the robot from the camera observations' poses.
// Frames are numbered from 0 in the order they come, whatever index the rawlog gave them.
//
// Damage: reading stops at the first damaged object; everything before it is used and `read`
// names the object (RawlogReader's wording). The caller decides whether that is enough.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/mrpt_plugin/local_enu_frame.h"
#include "omnisfm/mrpt_plugin/rawlog_input.h"
#include "omnisfm/sfm/motion_sensors.h"
#include "omnisfm/track/tracker_settings.h"

namespace mrpt::maps {
class CSimpleMap;
}

namespace omnisfm::mrpt_plugin {

enum class ReplayVision {
  kAuto,             // the tracked features when the rawlog has any, else its images
  kTrackedFeatures,  // CObservationTrackedFeatures only
  kImages,           // the images through the tracker, even when tracks are there
};

struct ReplayOptions {
  ReplayVision vision = ReplayVision::kAuto;
  std::string camera_label;                  // the camera's (or its tracks') sensor label
  std::string odometry_label, gyro_label, gps_label;  // empty: any
  // Replaces the models the rawlog carries; needed for stock CObservationImage.
  std::optional<camera::CatadioptricCamera> camera;
  track::TrackerSettings tracker;
  std::optional<GeodeticPoint> gps_origin;  // the ENU origin; default: the first fix
};

struct ReplayInput {
  std::optional<camera::CatadioptricCamera> camera;  // the given one, else the rawlog's first
  std::string vision;                                // "tracked features" or "images"
  std::vector<core::TrackObservation> tracks;          // sorted by frame, then track
  std::vector<double> frame_times;                   // per frame, seconds since the Unix epoch
  int frames_with_images = 0;  // camera observations that were images
  sfm::MotionSensors sensors;  // noise models left at their defaults
  std::optional<GeodeticPoint> gps_origin;  // the ENU origin used, when there were fixes
  std::size_t out_of_order = 0;  // motion readings dropped for coming back in time
  RawlogReadResult read;
};

// Called while images are tracked: (frames tracked, 0: the rawlog is read once, so the total is
// not known).
using ReplayProgress = std::function<void(int, int)>;

// Throws io::InputError when the file cannot be opened, and naming the image's object when images
// must be tracked without a camera (a stock CObservationImage and no `camera`) or an image is not
// the camera's size.
ReplayInput read_replay_input(const std::string& path, const ReplayOptions& options,
                              const ReplayProgress& progress = nullptr);
// The same from a simple map's sensory frames, in order (their poses are not used); messages name
// "the simple map".
ReplayInput read_replay_input(const mrpt::maps::CSimpleMap& map, const ReplayOptions& options,
                              const ReplayProgress& progress = nullptr);

}  // namespace omnisfm::mrpt_plugin
