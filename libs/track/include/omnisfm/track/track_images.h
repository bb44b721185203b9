#pragma once
// A whole image sequence through the tracker: the trackable region from the camera model, every
// frame tracked, and the tracks as shape-from-motion reads them.

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/track/feature_tracker.h"
#include "omnisfm/track/image_sequence.h"
#include "omnisfm/track/tracker_settings.h"

namespace omnisfm::track {

struct TrackedFrame {
  int index = 0;
  std::string file;                                             // empty for a video's frame
  double timestamp = std::numeric_limits<double>::quiet_NaN();  // seconds; NaN: none known
};

struct TrackedSequence {
  // Sorted by frame, then track; tracks seen in a single frame are left out (nothing to
  // triangulate, and tracks.vnl does not allow them).
  std::vector<core::TrackObservation> observations;
  int single_frame_tracks = 0;  // started, seen in one frame only, and left out
  std::vector<TrackedFrame> frames;
  TrackerStatistics statistics;
  double tracking_seconds = 0;  // in FeatureTracker::track, decoding and set-up excluded
};

// Called after each frame: (frames done, frames expected; 0 when unknown).
using TrackingProgress = std::function<void(int, int)>;

// The same, frame by frame, for images that come from elsewhere (a rawlog's observations).
class SequenceTracker {
 public:
  SequenceTracker(const camera::CatadioptricCamera& camera, const TrackerSettings& settings);
  ~SequenceTracker();
  SequenceTracker(const SequenceTracker&) = delete;
  SequenceTracker& operator=(const SequenceTracker&) = delete;

  // Tracks into `frame` (its index must be the number of frames added before) and returns the
  // tracks seen in it. Throws io::InputError naming `source` when the image is not the camera's
  // size.
  std::vector<TrackPixel> add(const SequenceFrame& frame, const std::string& source);
  int frames() const { return static_cast<int>(result_.frames.size()); }
  // The sequence so far, as track_images returns it.
  TrackedSequence finish() const;

 private:
  camera::CatadioptricCamera camera_;
  TrackerSettings settings_;
  std::unique_ptr<FeatureTracker> tracker_;
  std::vector<core::TrackObservation> all_;
  TrackedSequence result_;
};

// Throws io::InputError when an image is not the camera's size, and what ImageSequence throws.
TrackedSequence track_images(const camera::CatadioptricCamera& camera, ImageSequence& images,
                             const TrackerSettings& settings,
                             const TrackingProgress& progress = nullptr);

}  // namespace omnisfm::track
