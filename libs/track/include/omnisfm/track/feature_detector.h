#pragma once
// Shi-Tomasi corners inside the trackable region, spread over the image: about the mirror's axis
// the region is an annulus, divided into sectors (azimuth) and rings of equal area; new features
// go one at a time to the cell holding the fewest tracks, strongest corner first, so that the
// shape-from-motion sees every direction rather than the most textured one.

#include <opencv2/core.hpp>
#include <vector>

#include "omnisfm/track/tracker_settings.h"

namespace omnisfm::track {

class FeatureDetector {
 public:
  // region: CV_8UC1, 255 where features may be (valid_region_mask).
  FeatureDetector(const cv::Mat& region, const TrackerSettings& settings);

  // Corners in the region, at least min_distance_px from each other and from `live`, strongest
  // first, in full-resolution pixels. `level_image` is the image at detection_level (CV_8UC1,
  // the region's size halved detection_level times, as pyrDown makes it).
  std::vector<cv::Point2f> corners(const cv::Mat& level_image,
                                   const std::vector<cv::Point2f>& live) const;

  // Up to `count` of `candidates` (strongest first), spread over the cells given the tracks
  // already in `live`.
  std::vector<cv::Point2f> spread(const std::vector<cv::Point2f>& candidates,
                                  const std::vector<cv::Point2f>& live, int count) const;

  int cell(const cv::Point2f& point) const;
  const cv::Point2d& centre() const { return centre_; }

 private:
  // The region at detection_level: the pixels whose full-resolution counterpart is in it.
  cv::Mat level_region_;
  cv::Rect level_bounds_;   // of level_region_
  double level_scale_ = 1;  // full-resolution pixels per level pixel
  TrackerSettings settings_;
  cv::Point2d centre_;
  std::vector<double> ring_radii_squared_;  // of each ring's outer edge
};

}  // namespace omnisfm::track
