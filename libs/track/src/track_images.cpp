#include "omnisfm/track/track_images.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

#include "omnisfm/io/input_error.h"
#include "omnisfm/track/valid_region.h"

namespace omnisfm::track {

TrackedSequence track_images(const camera::CatadioptricCamera& camera, ImageSequence& images,
                             const TrackerSettings& settings, const TrackingProgress& progress) {
  using Clock = std::chrono::steady_clock;
  TrackedSequence result;
  const cv::Size size(camera.image_width(), camera.image_height());
  std::unique_ptr<FeatureTracker> tracker;
  std::vector<io::TrackObservation> all;
  SequenceFrame frame;
  double seconds = 0;
  while (images.next(&frame)) {
    if (frame.image.size() != size)
      throw io::InputError(frame.file.empty() ? images.path() : frame.file, 0,
                           "the image is " + std::to_string(frame.image.cols) + "x" +
                               std::to_string(frame.image.rows) + " but the camera's is " +
                               std::to_string(size.width) + "x" + std::to_string(size.height));
    if (!tracker)
      tracker = std::make_unique<FeatureTracker>(valid_region_mask(camera, settings.rim_margin_px),
                                                 settings);
    const auto started = Clock::now();
    for (const TrackedPoint& p : tracker->track(frame.image))
      all.push_back({frame.index, p.track, p.pixel});
    seconds += std::chrono::duration<double>(Clock::now() - started).count();
    result.frames.push_back({frame.index, frame.file, frame.timestamp});
    if (progress) progress(frame.index + 1, images.expected_frames());
  }

  std::map<int, int> seen;
  for (const auto& o : all) ++seen[o.track];
  for (const auto& o : all)
    if (seen[o.track] >= 2) result.observations.push_back(o);
  std::stable_sort(result.observations.begin(), result.observations.end(),
                   [](const io::TrackObservation& a, const io::TrackObservation& b) {
                     return a.frame != b.frame ? a.frame < b.frame : a.track < b.track;
                   });
  if (tracker) result.statistics = tracker->statistics();
  result.tracking_seconds = seconds;
  return result;
}

}  // namespace omnisfm::track
