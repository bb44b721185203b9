#include "tracks_drawing.h"

#include <algorithm>
#include <map>
#include <opencv2/imgproc.hpp>

namespace omnisfm::app {

cv::Mat draw_tracks(const cv::Mat& grey, const std::vector<core::TrackObservation>& observations,
                    int frame, int trail) {
  CV_Assert(grey.type() == CV_8UC1 && trail > 0);
  cv::Mat colour;
  cv::cvtColor(grey, colour, cv::COLOR_GRAY2BGR);
  std::map<int, int> first_frame;
  std::map<int, std::vector<cv::Point2f>> paths;  // of the tracks seen in `frame`, up to it
  for (const auto& o : observations) {
    first_frame.emplace(o.track, o.frame);
    if (o.frame <= frame && o.frame >= frame - trail)
      paths[o.track].emplace_back(static_cast<float>(o.pixel.x()),
                                  static_cast<float>(o.pixel.y()));
  }
  for (const auto& o : observations) {
    if (o.frame != frame) continue;
    const double age = std::min(1.0, static_cast<double>(frame - first_frame[o.track]) / trail);
    const cv::Scalar bgr(255 * (1 - age), 64, 255 * age);
    // Sub-pixel drawing: 4 fractional bits.
    constexpr int kShift = 4;
    std::vector<cv::Point> points;
    for (const cv::Point2f& p : paths[o.track])
      points.emplace_back(cvRound(p.x * (1 << kShift)), cvRound(p.y * (1 << kShift)));
    cv::polylines(colour, points, false, bgr, 1, cv::LINE_AA, kShift);
    cv::circle(colour, points.back(), 2 << kShift, bgr, cv::FILLED, cv::LINE_AA, kShift);
  }
  return colour;
}

}  // namespace omnisfm::app
