// The tracker on a real catadioptric photograph turned about a point, frame by frame (not a
// benchmark: one run, one report). A rig turning about its mirror's axis turns its image about the
// axis's pixel; here the photograph is turned about its centre, which needs no calibration, and
// every pixel's true place in every frame is known exactly. The texture is the world's, not the
// simulator's: the shared real sets' rooms, boards and people. Each frame is the photograph
// resampled (Lanczos), with Gaussian noise and 8 bits; the truth of a track is where the turn
// takes the point its first observation showed.
//   real_image_rotation IMAGE [FRAMES=120] [DEG_PER_FRAME=0.5] [NOISE=2] [SEED=1]
// Prints the tracks' count, their median length, the error against the truth (median, 95th
// percentile, beyond 1 px) and the reacquisitions that came back off their point.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "omnisfm/core/percentile.h"
#include "omnisfm/track/feature_tracker.h"

namespace {

using namespace omnisfm;

// The 2 x 3 map from the photograph's pixels to frame f's.
cv::Matx23d turn(const cv::Point2d& centre, double degrees) {
  return cv::getRotationMatrix2D(centre, degrees, 1.0);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: real_image_rotation IMAGE [FRAMES=120] [DEG_PER_FRAME=0.5] [NOISE=2] "
                 "[SEED=1]\n");
    return 2;
  }
  const cv::Mat photo = cv::imread(argv[1], cv::IMREAD_GRAYSCALE);
  if (photo.empty()) {
    std::fprintf(stderr, "real_image_rotation: %s: not an image\n", argv[1]);
    return 2;
  }
  const int frames = argc > 2 ? std::atoi(argv[2]) : 120;
  const double step_deg = argc > 3 ? std::atof(argv[3]) : 0.5;
  const double noise = argc > 4 ? std::atof(argv[4]) : 2;
  const int seed = argc > 5 ? std::atoi(argv[5]) : 1;

  // Tracks inside the disc that stays in the photograph whatever the turn, less a margin.
  const cv::Point2d centre(0.5 * (photo.cols - 1), 0.5 * (photo.rows - 1));
  const int radius = std::min(photo.cols, photo.rows) / 2 - 30;
  cv::Mat region(photo.size(), CV_8UC1, cv::Scalar(0));
  cv::circle(region, cv::Point(photo.cols / 2, photo.rows / 2), radius, 255, cv::FILLED);

  track::TrackerSettings settings;
  track::FeatureTracker tracker(region, settings);
  cv::RNG rng(seed);
  std::map<int, cv::Point2d> photo_point;  // of each track
  std::map<int, int> first_frame, last_frame, gaps;
  std::map<int, double> worst;
  std::vector<double> errors;
  for (int f = 0; f < frames; ++f) {
    const cv::Matx23d map = turn(centre, f * step_deg);
    cv::Mat turned;
    cv::warpAffine(photo, turned, map, photo.size(), cv::INTER_LANCZOS4, cv::BORDER_REFLECT_101);
    cv::Mat noisy(turned.size(), CV_32FC1);
    rng.fill(noisy, cv::RNG::NORMAL, 0, noise);
    noisy += cv::Mat_<float>(turned);
    noisy.convertTo(turned, CV_8UC1);  // rounds and saturates
    for (const auto& seen : tracker.track(turned)) {
      const cv::Point2d pixel(seen.pixel.x(), seen.pixel.y());
      if (!photo_point.count(seen.track)) {
        cv::Matx23d back;
        cv::invertAffineTransform(map, back);
        photo_point[seen.track] = back * cv::Vec3d(pixel.x, pixel.y, 1);
        first_frame[seen.track] = last_frame[seen.track] = f;
        continue;
      }
      if (last_frame[seen.track] != f - 1) ++gaps[seen.track];
      last_frame[seen.track] = f;
      const cv::Point2d& q = photo_point[seen.track];
      const cv::Vec2d truth = map * cv::Vec3d(q.x, q.y, 1);
      const double error = std::hypot(pixel.x - truth[0], pixel.y - truth[1]);
      errors.push_back(error);
      worst[seen.track] = std::max(worst[seen.track], error);
    }
  }
  std::vector<double> lengths;
  int astray = 0, reacquired_off = 0, reacquired = 0;
  for (const auto& [id, first] : first_frame) {
    if (last_frame[id] == first) continue;  // seen once: tracks.vnl leaves these out
    lengths.push_back(last_frame[id] - first + 1);
    astray += worst[id] > 1;
    if (gaps[id] > 0) {
      reacquired += gaps[id];
      reacquired_off += worst[id] > 1;
    }
  }
  const track::TrackerStatistics& s = tracker.statistics();
  std::printf(
      "%s, %d frames at %.2f deg, noise %.1f: %zu tracks, median length %.0f frames, error "
      "median %.3f px, p95 %.3f px, max %.3f px, %d beyond 1 px (%.2f %%); %d reacquired after "
      "a gap, %d of those tracks beyond 1 px\n",
      argv[1], frames, step_deg, noise, lengths.size(), core::percentile(lengths, 0.5),
      core::percentile(errors, 0.5), core::percentile(errors, 0.95), core::percentile(errors, 1),
      astray, lengths.empty() ? 0.0 : 100.0 * astray / lengths.size(), reacquired, reacquired_off);
  std::printf("ended: lost %d, appearance %d, misfit %d, reshaped %d, jumped %d, left region %d\n",
              s.lost, s.appearance, s.misfit, s.reshaped, s.jumped, s.left_region);
  return 0;
}
