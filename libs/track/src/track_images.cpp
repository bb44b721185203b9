#include "omnisfm/track/track_images.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

#include "omnisfm/io/input_error.h"
#include "omnisfm/track/valid_region.h"

namespace omnisfm::track {

SequenceTracker::SequenceTracker(const camera::CatadioptricCamera& camera,
                                 const TrackerSettings& settings)
    : camera_(camera), settings_(settings) {}

SequenceTracker::~SequenceTracker() = default;

std::vector<TrackPixel> SequenceTracker::add(const SequenceFrame& frame,
                                               const std::string& source) {
  using Clock = std::chrono::steady_clock;
  const cv::Size size(camera_.image_width(), camera_.image_height());
  if (frame.image.size() != size)
    throw io::InputError(source, 0,
                         "the image is " + std::to_string(frame.image.cols) + "x" +
                             std::to_string(frame.image.rows) + " but the camera's is " +
                             std::to_string(size.width) + "x" + std::to_string(size.height));
  if (!tracker_)
    tracker_ = std::make_unique<FeatureTracker>(
        valid_region_mask(camera_, settings_.rim_margin_px), settings_);
  const auto started = Clock::now();
  std::vector<TrackPixel> seen = tracker_->track(frame.image);
  result_.tracking_seconds += std::chrono::duration<double>(Clock::now() - started).count();
  for (const TrackPixel& p : seen) all_.push_back({frame.index, p.track, p.pixel});
  result_.frames.push_back({frame.index, frame.file, frame.timestamp});
  return seen;
}

TrackedSequence SequenceTracker::finish() const {
  TrackedSequence result = result_;
  std::map<int, int> seen;
  for (const auto& o : all_) ++seen[o.track];
  for (const auto& o : all_)
    if (seen[o.track] >= 2) result.observations.push_back(o);
  for (const auto& [track, count] : seen) result.single_frame_tracks += count == 1;
  std::stable_sort(result.observations.begin(), result.observations.end(),
                   [](const core::TrackObservation& a, const core::TrackObservation& b) {
                     return a.frame != b.frame ? a.frame < b.frame : a.track < b.track;
                   });
  if (tracker_) result.statistics = tracker_->statistics();
  return result;
}

TrackedSequence track_images(const camera::CatadioptricCamera& camera, ImageSequence& images,
                             const TrackerSettings& settings, const TrackingProgress& progress) {
  SequenceTracker tracker(camera, settings);
  SequenceFrame frame;
  while (images.next(&frame)) {
    tracker.add(frame, frame.file.empty() ? images.path() : frame.file);
    if (progress) progress(frame.index + 1, images.expected_frames());
  }
  return tracker.finish();
}

}  // namespace omnisfm::track
