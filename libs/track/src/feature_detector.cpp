#include "omnisfm/track/feature_detector.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "omnisfm/track/valid_region.h"
#include "shi_tomasi.h"

namespace omnisfm::track {

FeatureDetector::FeatureDetector(const cv::Mat& region, const TrackerSettings& settings)
    : settings_(settings), centre_(region_centre(region)) {
  CV_Assert(region.type() == CV_8UC1 && settings.sectors >= 1 && settings.rings >= 1);
  CV_Assert(settings.detection_level >= 0);
  level_scale_ = std::ldexp(1.0, settings.detection_level);
  cv::Size level_size = region.size();
  for (int l = 0; l < settings.detection_level; ++l)
    level_size = cv::Size((level_size.width + 1) / 2, (level_size.height + 1) / 2);
  level_region_.create(level_size, CV_8UC1);
  for (int y = 0; y < level_size.height; ++y) {
    uchar* out = level_region_.ptr<uchar>(y);
    const int fy = static_cast<int>(y * level_scale_);
    if (fy >= region.rows) {
      std::fill(out, out + level_size.width, uchar{0});
      continue;
    }
    const uchar* in = region.ptr<uchar>(fy);
    for (int x = 0; x < level_size.width; ++x) {
      const int fx = static_cast<int>(x * level_scale_);
      out[x] = fx < region.cols ? in[fx] : 0;
    }
  }
  level_bounds_ = cv::boundingRect(level_region_);

  // Equal-area rings between the region's nearest and farthest pixels from the centre. A tracker
  // is made per sequence, but reading every pixel of a large region cost more than a few frames:
  // per row, the farthest pixel is one of its ends, and the nearest is the first one found
  // walking out from the centre's column either way.
  const cv::Rect bounds = cv::boundingRect(region);
  double r2_min = 1e300, r2_max = 0;
  const int left_of_centre = static_cast<int>(std::floor(centre_.x));
  for (int y = bounds.y; y < bounds.y + bounds.height; ++y) {
    const uchar* inside = region.ptr<uchar>(y);
    int first = bounds.x, last = bounds.x + bounds.width - 1;
    while (first <= last && !inside[first]) ++first;
    if (first > last) continue;
    while (!inside[last]) --last;
    const double dy = y - centre_.y;
    const auto r2 = [&](int x) { return (x - centre_.x) * (x - centre_.x) + dy * dy; };
    r2_max = std::max({r2_max, r2(first), r2(last)});
    int left = std::min(left_of_centre, last);
    while (left >= first && !inside[left]) --left;
    int right = std::max(left_of_centre + 1, first);
    while (right <= last && !inside[right]) ++right;
    if (left >= first) r2_min = std::min(r2_min, r2(left));
    if (right <= last) r2_min = std::min(r2_min, r2(right));
  }
  for (int i = 1; i <= settings.rings; ++i)
    ring_radii_squared_.push_back(r2_min + (r2_max - r2_min) * i / settings.rings);
}

int FeatureDetector::cell(const cv::Point2f& point) const {
  const double dx = point.x - centre_.x, dy = point.y - centre_.y;
  const double r2 = dx * dx + dy * dy;
  int ring = 0;
  while (ring + 1 < static_cast<int>(ring_radii_squared_.size()) && r2 > ring_radii_squared_[ring])
    ++ring;
  const double turn = (std::atan2(dy, dx) + M_PI) / (2 * M_PI);
  const int sector = std::min(settings_.sectors - 1, static_cast<int>(turn * settings_.sectors));
  return ring * settings_.sectors + sector;
}

std::vector<cv::Point2f> FeatureDetector::corners(const cv::Mat& level_image,
                                                  const std::vector<cv::Point2f>& live) const {
  CV_Assert(level_image.type() == CV_8UC1 && level_image.size() == level_region_.size());
  if (level_bounds_.empty()) return {};
  const double level_distance = settings_.min_distance_px / level_scale_;
  cv::Mat allowed = level_region_(level_bounds_).clone();
  for (const auto& p : live)
    cv::circle(allowed,
               cv::Point(cvRound(p.x / level_scale_) - level_bounds_.x,
                         cvRound(p.y / level_scale_) - level_bounds_.y),
               static_cast<int>(std::ceil(level_distance)), 0, cv::FILLED);
  // Enough candidates for every cell to choose from.
  const int wanted = 2 * settings_.max_tracks + 32;
  std::vector<cv::Point2f> found = shi_tomasi_corners(
      level_image(level_bounds_), wanted, settings_.quality_level, level_distance, allowed);
  const float scale = static_cast<float>(level_scale_);
  for (auto& p : found)
    p = cv::Point2f((p.x + level_bounds_.x) * scale, (p.y + level_bounds_.y) * scale);
  return found;
}

std::vector<cv::Point2f> FeatureDetector::spread(const std::vector<cv::Point2f>& candidates,
                                                 const std::vector<cv::Point2f>& live,
                                                 int count) const {
  std::vector<int> occupancy(settings_.rings * settings_.sectors, 0);
  for (const auto& p : live) ++occupancy[cell(p)];
  // Per cell, its candidates strongest first.
  std::vector<std::vector<cv::Point2f>> per_cell(occupancy.size());
  for (const auto& p : candidates) per_cell[cell(p)].push_back(p);
  std::vector<size_t> next(occupancy.size(), 0);
  std::vector<cv::Point2f> chosen;
  while (static_cast<int>(chosen.size()) < count) {
    int best = -1;
    for (size_t c = 0; c < per_cell.size(); ++c)
      if (next[c] < per_cell[c].size() && (best < 0 || occupancy[c] < occupancy[best]))
        best = static_cast<int>(c);
    if (best < 0) break;
    chosen.push_back(per_cell[best][next[best]++]);
    ++occupancy[best];
  }
  return chosen;
}

}  // namespace omnisfm::track
