#include "omnisfm/track/feature_tracker.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>
#include <type_traits>

#include "omnisfm/core/percentile.h"
#include "duplicate_tracks.h"
#include "gaussian_blur.h"
#include "square_correlation.h"
#include "step_neighbourhoods.h"

namespace omnisfm::track {
namespace {

constexpr int kMaxAlignmentIterations = 20;
constexpr size_t kRecentPositions = 8;
// The latest positions left out of the velocity a lost track is looked for with.
constexpr size_t kSkippedRecent = 3;
// A track's step is compared with its neighbours' only where it has this many.
constexpr size_t kMinNeighbours = 3;
// How many frames a track too young for that velocity is looked for (FeatureTracker::reacquire).
constexpr int kYoungMaxGap = 3;
// Around the region's bounding box: room for the coarsest pyramid level's window and for ORB.
constexpr int kBoundsBorder = 40;
// A step of the feature below this ends the alignment (and is taken): what is left after it is
// 0.001 px at the median on the realistic rover (0.002 in the lab), a fiftieth of the tracks'
// median error. At 0.005 px the rover's alignments took 3.2 iterations each, where they take 2.7.
constexpr double kAlignmentTolerancePx = 0.01;
// A reference's template is blurred anew once the Gaussian its patch's shape asks for has
// changed by this much (px^2 along a direction; ReferencePatch::match_blur): at the realistic
// images' blur, about every 15 % of shrinking. At 0.1 the realistic rover took 31 blurred
// templates a frame where 0.3 took 10, and no set's errors were the smaller; at 0.5 the lab's
// 95th percentile was 0.30 px at seeds 1-3.
constexpr double kBlurMatchTolerance = 0.3;

cv::Point2f point(const Eigen::Vector2d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y())};
}

Eigen::Vector2d vector(const cv::Point2f& p) { return {p.x, p.y}; }

cv::Mat half_sizes(const cv::Mat& image, int times) {
  cv::Mat smaller = image;
  for (int i = 0; i < times; ++i) cv::pyrDown(smaller, smaller);
  return smaller;
}

cv::Rect bordered_bounds(const cv::Mat& region) {
  CV_Assert(region.type() == CV_8UC1 && cv::countNonZero(region) > 0);
  const cv::Rect box = cv::boundingRect(region);
  const cv::Rect grown(box.x - kBoundsBorder, box.y - kBoundsBorder, box.width + 2 * kBoundsBorder,
                       box.height + 2 * kBoundsBorder);
  return grown & cv::Rect(0, 0, region.cols, region.rows);
}

}  // namespace

FeatureTracker::FeatureTracker(const cv::Mat& region, const TrackerSettings& settings)
    : image_size_(region.size()),
      bounds_(bordered_bounds(region)),
      region_(region(bounds_).clone()),
      settings_(settings),
      detector_(region_, settings) {
  // Tracks move around in vectors every frame: copying them would cost more than tracking.
  static_assert(std::is_nothrow_move_constructible_v<Track>);
  CV_Assert(settings.max_tracks >= 0 && settings.lk_window >= 3 && settings.pyramid_levels >= 1 &&
            settings.prediction_level >= 0 && settings.prediction_level < settings.pyramid_levels &&
            settings.patch_half_size >= 1 && settings.min_followable_ncc >= 0 &&
            settings.min_followable_ncc < 1 && settings.max_renewals >= 0 &&
            settings.detect_at_missing >= 1 && settings.neighbourhood_radius_px > 0 &&
            settings.camera_blur_px >= 0);
}

cv::Mat FeatureTracker::alignment_image(const cv::Mat& image) const {
  if (settings_.image_blur_sigma > 0)
    return gaussian_blurred_float(image, settings_.image_blur_sigma);
  cv::Mat converted;
  image.convertTo(converted, CV_32F);
  return converted;
}

int FeatureTracker::lucas_kanade_finest_level() const {
  return settings_.refine ? settings_.prediction_level : 0;
}

bool FeatureTracker::in_region(const Eigen::Vector2d& p) const {
  const int x = static_cast<int>(std::lround(p.x())), y = static_cast<int>(std::lround(p.y()));
  return x >= 0 && y >= 0 && x < region_.cols && y < region_.rows && region_.at<uchar>(y, x);
}

std::vector<TrackPixel> FeatureTracker::track(const cv::Mat& full_image) {
  CV_Assert(full_image.type() == CV_8UC1 && full_image.size() == image_size_);
  ++frame_;
  ++statistics_.frames;
  image_ = full_image(bounds_);
  aligned_image_ = alignment_image(image_);
  previous_pyramid_.swap(pyramid_);
  const int finest = lucas_kanade_finest_level();
  cv::buildOpticalFlowPyramid(half_sizes(image_, finest), pyramid_,
                              cv::Size(settings_.lk_window, settings_.lk_window),
                              settings_.pyramid_levels - 1 - finest, true);
  if (frame_ > 0) {
    follow_live_tracks();
    end_jumped_tracks();
    remove_duplicates();
  }
  replenish();

  std::vector<TrackPixel> seen;
  seen.reserve(live_.size());
  const Eigen::Vector2d corner(bounds_.x, bounds_.y);
  for (const Track& t : live_) seen.push_back({t.id, t.position + t.warp.A * t.reported + corner});
  return seen;
}

void FeatureTracker::end_track(size_t index, int* counter, bool may_return) {
  ++*counter;
  if (!may_return) return;
  // Only a feature that looked like itself until it vanished can be seen again: one that faded
  // (its look changing with the viewpoint) will not match its reference any better later.
  Track& t = live_[index];
  // Remembered while it was last seen inside the region, wherever its motion would take it: near
  // the rim the image paths curve, and a straight extrapolation leaves the region where the feature
  // does not (the realistic rover, seed 1: 19 reacquisitions, all right, against 10).
  // Nor one seen in a single frame: never followed, its look was never confirmed (the realistic
  // sets' one wrong reacquisition, seeds 1-3, was such a track, 1.2 px off).
  if (!settings_.reacquire || t.ncc < settings_.sudden_loss_ncc || !in_region(t.position) ||
      t.last_frame == t.first_frame)
    return;
  if (!t.descriptor.valid) {  // not yet described: lost for the first time
    t.descriptor = describe(t.first_look, 0);
    t.first_look = FeatureSurroundings();
  }
  if (t.descriptor.valid) lost_.push_back(std::move(t));
}

template <typename Keep>
void FeatureTracker::keep_live_tracks(Keep keep) {
  // In place: a vector of the kept tracks made anew cost its allocation four times a frame and,
  // once new tracks were added, a reallocation.
  size_t kept = 0;
  for (size_t i = 0; i < live_.size(); ++i) {
    if (!keep(i)) continue;
    if (kept != i) live_[kept] = std::move(live_[i]);
    ++kept;
  }
  live_.erase(live_.begin() + static_cast<std::ptrdiff_t>(kept), live_.end());
}

void FeatureTracker::follow_live_tracks() {
  if (live_.empty()) return;
  // Pixels of the pyramid's finest level.
  const int finest = lucas_kanade_finest_level();
  const double to_level = 1.0 / (1 << finest);
  std::vector<cv::Point2f> previous, predicted, back;
  for (const Track& t : live_) {
    previous.push_back(point(to_level * t.position));
    predicted.push_back(point(to_level * (t.position + t.velocity)));
  }
  const cv::Size window(settings_.lk_window, settings_.lk_window);
  // Lucas-Kanade only predicts (the reference alignment measures), and where asked checks
  // consistency to max_forward_backward_px: a few hundredths of a pixel is enough.
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.03);
  std::vector<uchar> forward_ok, backward_ok(live_.size(), 1);
  // No error output: OpenCV then skips computing each point's patch difference.
  cv::calcOpticalFlowPyrLK(previous_pyramid_, pyramid_, previous, predicted, forward_ok, cv::noArray(),
                           window, settings_.pyramid_levels - 1 - finest, criteria,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  // Back from where the step ends, starting where it began: a consistent step returns there
  // (within max_forward_backward_px, well inside the window) on the finest level alone, and an
  // inconsistent one ends whether it fails to converge there or converges too far away.
  const bool check_back = (!settings_.refine || settings_.forward_backward_with_refinement) &&
                          settings_.max_forward_backward_px > 0;
  if (check_back) {
    back = previous;
    cv::calcOpticalFlowPyrLK(pyramid_, previous_pyramid_, predicted, back, backward_ok,
                             cv::noArray(), window, 0, criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
  }

  std::vector<double> residuals;
  const double blur_variance = settings_.blur_variance();
  keep_live_tracks([&](size_t i) {
    // The next track's pixels are fetched while this one is aligned: the blurred image is read
    // first here, from beyond the fastest caches.
    if (settings_.refine && i + 1 < live_.size())
      ReferencePatch::prefetch(aligned_image_, vector(predicted[i + 1]) / to_level,
                               settings_.patch_half_size);
    Track& t = live_[i];
    if (!forward_ok[i] || !backward_ok[i]) {
      end_track(i, &statistics_.lost);
      return false;
    }
    if (check_back &&
        (vector(back[i]) / to_level - t.position).norm() > settings_.max_forward_backward_px) {
      end_track(i, &statistics_.forward_backward);
      return false;
    }
    const Eigen::Vector2d prediction = vector(predicted[i]) / to_level;
    // The patch's shape changes steadily as the feature crosses the mirror or comes closer: the
    // last step's change, taken again, starts the alignment nearer its end.
    AffineWarp warp = t.warp;
    warp.A = t.shape_step * t.warp.A;
    warp.b = prediction;
    AlignmentResult aligned;
    if (settings_.refine) {
      aligned =
          t.reference.align(aligned_image_, &warp, kMaxAlignmentIterations, kAlignmentTolerancePx);
    } else {
      aligned.converged = true;
      aligned.ncc = t.reference.ncc(aligned_image_, warp);
    }
    if (!aligned.converged || aligned.ncc < settings_.min_ncc ||
        (warp.b - prediction).norm() > settings_.max_refinement_shift_px) {
      end_track(i, &statistics_.appearance);
      return false;
    }
    if (settings_.refine && aligned.misfit_px > settings_.max_misfit_px) {
      end_track(i, &statistics_.misfit, false);
      return false;
    }
    const double distortion = patch_distortion(warp.A);
    if (distortion > settings_.max_patch_distortion) {
      end_track(i, &statistics_.reshaped, false);
      return false;
    }
    if (!in_region(warp.b)) {
      end_track(i, &statistics_.left_region, false);
      return false;
    }
    if (settings_.refine) residuals.push_back(aligned.residual_rms);
    const Eigen::Matrix2d shape_step = warp.A * t.warp.A.inverse();
    double ncc = aligned.ncc;
    if (settings_.refine && t.renewals < settings_.max_renewals &&
        aligned.misfit_px <= 0.5 * settings_.max_misfit_px &&
        (aligned.ncc < 0.5 * (1 + settings_.min_ncc) ||
         distortion > 0.5 * settings_.max_patch_distortion)) {
      ReferencePatch renewed;
      if (ReferencePatch::extract(aligned_image_, warp.b, settings_.patch_half_size, &renewed)) {
        // The patch as it now looks, and, should the track be lost, its surroundings as they now
        // look: reacquisition compares with both.
        t.reference = std::move(renewed);
        t.reported = warp.A * t.reported;
        warp.A.setIdentity();
        ncc = 1;
        if (settings_.reacquire) {
          t.first_look = surroundings(image_, point(warp.b));
          t.descriptor = Descriptor();
        }
        ++t.renewals;
        ++statistics_.renewed;
      }
    }
    if (settings_.refine && t.reference.match_blur(warp.A, blur_variance, kBlurMatchTolerance))
      ++statistics_.smoothed_anew;
    t.velocity = warp.b - t.position;
    t.position = warp.b;
    t.warp = warp;
    t.shape_step = shape_step;
    t.last_frame = frame_;
    t.ncc = ncc;
    t.recent.push_back(t.position);
    if (t.recent.size() > kRecentPositions) t.recent.erase(t.recent.begin());
    return true;
  });
  estimate_noise(std::move(residuals));
}

void FeatureTracker::estimate_noise(std::vector<double> residuals) {
  // The median: a few tracks whose look the warp no longer follows leave more.
  constexpr size_t kMinTracks = 10;
  if (residuals.size() < kMinTracks) return;
  const double noise = core::percentile(std::move(residuals), 0.5) / std::sqrt(2.0);
  // The camera's noise changes slowly, with the exposure.
  constexpr double kNewWeight = 0.3;
  noise_ = noise_ > 0 ? (1 - kNewWeight) * noise_ + kNewWeight * noise : noise;
}

StepNeighbourhoods FeatureTracker::live_steps() const {
  std::vector<Eigen::Vector2d> starts, steps;
  starts.reserve(live_.size());
  steps.reserve(live_.size());
  for (const Track& t : live_) {
    starts.push_back(t.position - t.velocity);
    steps.push_back(t.velocity);
  }
  return StepNeighbourhoods(std::move(starts), std::move(steps),
                            settings_.neighbourhood_radius_px);
}

void FeatureTracker::end_jumped_tracks() {
  const StepNeighbourhoods neighbourhoods = live_steps();
  std::vector<bool> jumped(live_.size(), false);
  for (size_t i = 0; i < live_.size(); ++i) {
    jumped[i] = neighbourhoods.departs(live_[i].position - live_[i].velocity, i, kMinNeighbours,
                                       live_[i].velocity, settings_.max_step_deviation_px);
  }
  keep_live_tracks([&](size_t i) {
    if (jumped[i]) end_track(i, &statistics_.jumped, false);
    return !jumped[i];
  });
}

void FeatureTracker::remove_duplicates() {
  std::vector<Eigen::Vector2d> positions;
  std::vector<std::pair<int, int>> started;
  for (const Track& t : live_) {
    positions.push_back(t.position);
    started.emplace_back(t.first_frame, t.id);
  }
  const std::vector<bool> ended =
      younger_duplicates(positions, started, settings_.min_track_separation_px);
  keep_live_tracks([&](size_t i) {
    if (ended[i]) ++statistics_.duplicate;  // not worth reacquiring: another track has it
    return !ended[i];
  });
}

bool FeatureTracker::start_track(const cv::Point2f& at, int id) {
  Track t;
  // 1 - noise^2 / contrast^2 >= min_followable_ncc. While fewer than half of max_tracks are
  // alive the scene offers little better: a faint track then beats none (the realistic crane at
  // half size kept 17 tracks over 60 frames without that exception).
  double min_contrast = 0;
  if (noise_ > 0 && settings_.min_followable_ncc > 0 &&
      2 * static_cast<int>(live_.size()) >= settings_.max_tracks)
    min_contrast = noise_ / std::sqrt(1 - settings_.min_followable_ncc);
  if (min_contrast > 0 &&
      ReferencePatch::contrast_at(aligned_image_, vector(at), settings_.patch_half_size) <
          min_contrast) {
    ++statistics_.too_faint;
    return false;
  }
  if (!ReferencePatch::extract(aligned_image_, vector(at), settings_.patch_half_size, &t.reference))
    return false;
  t.id = id;
  t.first_frame = t.last_frame = frame_;
  t.position = vector(at);
  t.warp.b = t.position;
  t.reported = t.reference.best_located_offset();
  t.recent.push_back(t.position);
  // Kept to be described as it looked when its reference was taken, should it be lost: by
  // then an occluder may cover it.
  if (settings_.reacquire) t.first_look = surroundings(image_, at);
  live_.push_back(std::move(t));
  return true;
}

void FeatureTracker::replenish() {
  while (!lost_.empty() && frame_ - lost_.front().last_frame > settings_.reacquire_frames)
    lost_.pop_front();
  std::vector<cv::Point2f> corners;
  const int missing = settings_.max_tracks - static_cast<int>(live_.size());
  if (missing > 0 && missing >= std::min(settings_.detect_at_missing,
                                         std::max(1, settings_.max_tracks / 8))) {
    std::vector<cv::Point2f> live_points;
    for (const Track& t : live_) live_points.push_back(point(t.position));
    // The pyramid holds each level's image then its derivatives, from the finest level
    // Lucas-Kanade works on.
    const int in_pyramid = settings_.detection_level - lucas_kanade_finest_level();
    const cv::Mat level_image =
        in_pyramid >= 0 && 2 * in_pyramid < static_cast<int>(pyramid_.size())
            ? pyramid_[2 * in_pyramid]
            : half_sizes(image_, settings_.detection_level);
    corners = detector_.corners(level_image, live_points);
  }
  std::vector<cv::Point2f> reacquired;
  if (settings_.reacquire && !lost_.empty()) reacquire(&corners, &reacquired);

  std::vector<cv::Point2f> fresh;
  for (const cv::Point2f& c : corners) {
    // Corners kept their distance from the tracks alive before, not from those just reacquired.
    const bool crowded = std::any_of(
        reacquired.begin(), reacquired.end(),
        [&](const cv::Point2f& p) { return cv::norm(p - c) < settings_.min_distance_px; });
    if (!crowded) fresh.push_back(c);
  }
  const int wanted = settings_.max_tracks - static_cast<int>(live_.size());
  if (wanted <= 0) return;
  std::vector<cv::Point2f> live_points;
  for (const Track& t : live_) live_points.push_back(point(t.position));
  // In the spread's order, past corners too flat to start a track on.
  int started = 0;
  const int all = static_cast<int>(fresh.size());
  for (const cv::Point2f& at : detector_.spread(fresh, live_points, all)) {
    if (started == wanted) break;
    if (!start_track(at, next_id_)) continue;
    ++next_id_;
    ++started;
    ++statistics_.started;
  }
}

Eigen::Vector2d FeatureTracker::Track::predicted(int frame) const {
  // The image velocity from before the last few frames, which an occluder that is creeping over
  // the feature may have biased; unknown for a young track (see reacquire), left where it was.
  if (!moved_long_enough()) return position;
  const Eigen::Vector2d earlier_velocity =
      (recent[recent.size() - 1 - kSkippedRecent] - recent.front()) /
      static_cast<double>(recent.size() - 1 - kSkippedRecent);
  return position + (frame - last_frame) * earlier_velocity;
}

bool FeatureTracker::Track::moved_long_enough() const {
  return recent.size() > kSkippedRecent + 1;
}

bool FeatureTracker::repeated_nearby(const Track& t, const AffineWarp& found,
                                     double radius) const {
  // Scanned every other pixel (a look-alike's correlation peak is wider than that), and aligned
  // from where the reference, unaligned, correlates kTwinStartNcc or better; the match's own
  // peak converges back onto it.
  constexpr int kStep = 2;
  constexpr double kTwinStartNcc = 0.9;
  const Eigen::Vector2d centre = found.b;
  const double apart = t.reference.half_size();
  const int reach = static_cast<int>(std::ceil(radius));
  // First the plain correlation of the square about the place found with the square about each
  // place (SquareCorrelation), where both fit in the image: where that is below kLooseNcc the
  // reference's weighted correlation, two thirds of the reacquisition's time, is not computed. A
  // look-alike correlates highly on both; with this filter the reacquisitions on every rendered
  // set are those without it.
  constexpr float kLooseNcc = 0.5f;
  const int half = t.reference.half_size();
  const cv::Point pixel(static_cast<int>(std::lround(centre.x())),
                        static_cast<int>(std::lround(centre.y())));
  std::optional<SquareCorrelation> plain;
  if (SquareCorrelation::fits(aligned_image_, pixel, half))
    plain.emplace(aligned_image_, pixel, half);
  std::vector<Eigen::Vector2d> tried;  // where alignments ended: their peaks need no second try
  AffineWarp warp = found;
  for (int dy = -reach; dy <= reach; dy += kStep)
    for (int dx = -reach; dx <= reach; dx += kStep) {
      const Eigen::Vector2d at = centre + Eigen::Vector2d(dx, dy);
      if ((at - centre).norm() > radius || (at - found.b).norm() <= apart || !in_region(at))
        continue;
      if (plain) {
        const cv::Point square(static_cast<int>(std::lround(at.x())),
                               static_cast<int>(std::lround(at.y())));
        if (plain->fits(square) && plain->at(square) < kLooseNcc) continue;
      }
      warp = found;
      warp.b = at;
      if (t.reference.ncc(aligned_image_, warp) < kTwinStartNcc) continue;
      if (std::any_of(tried.begin(), tried.end(),
                      [&](const Eigen::Vector2d& p) { return (p - at).norm() <= apart; }))
        continue;
      const AlignmentResult aligned =
          t.reference.align(aligned_image_, &warp, kMaxAlignmentIterations, kAlignmentTolerancePx);
      tried.push_back(warp.b);
      if (aligned.converged && aligned.ncc >= settings_.twin_ncc &&
          (warp.b - found.b).norm() > apart && in_region(warp.b))
        return true;
    }
  return false;
}

namespace {

// Within this, two alignments found the same place.
constexpr double kSamePositionPx = 1.0;
// A start where the reference correlates this little is not near the feature: not worth an
// alignment.
constexpr double kMinStartNcc = 0.25;
// How far about the place found twins are looked for: three search radii (a prediction may be
// off by more than the disc: the feature turned up elsewhere while hidden, and a twin into it),
// and at least four patch widths (texture that repeats that closely is ambiguous whatever the
// gap).
constexpr double kRepeatReach = 3;
constexpr double kRepeatMinReachPatches = 4;

}  // namespace

std::vector<FeatureTracker::Place> FeatureTracker::reacquisition_starts(
    const Track& t, const Eigen::Vector2d& predicted, double radius,
    const std::vector<cv::Point2f>& corners, const std::vector<bool>& corner_used,
    const std::vector<bool>& young_ended) const {
  std::vector<Place> starts(1);
  starts[0].warp.b = predicted;
  int nearest_corner = -1;
  double corner_distance = INFINITY;
  for (size_t c = 0; c < corners.size(); ++c) {
    const double distance = (vector(corners[c]) - predicted).norm();
    if (!corner_used[c] && distance <= radius && distance < corner_distance) {
      nearest_corner = static_cast<int>(c);
      corner_distance = distance;
    }
  }
  if (nearest_corner >= 0) {
    starts.emplace_back();
    starts.back().warp.b = vector(corners[nearest_corner]);
  }
  int nearest_young = -1;
  double young_distance = radius;
  for (size_t i = 0; i < live_.size(); ++i) {
    const double distance = (live_[i].position - predicted).norm();
    if (!young_ended[i] && live_[i].first_frame > t.last_frame && distance <= young_distance) {
      nearest_young = static_cast<int>(i);
      young_distance = distance;
    }
  }
  if (nearest_young >= 0) {
    starts.emplace_back();
    starts.back().warp.b = live_[nearest_young].position;
    starts.back().young = nearest_young;
  }
  return starts;
}

std::vector<FeatureTracker::Place> FeatureTracker::places_found(
    const Track& t, const std::vector<Place>& starts, const Eigen::Vector2d& predicted,
    double radius) const {
  std::vector<Place> found;
  for (const Place& start : starts) {
    AffineWarp warp = t.warp;
    warp.b = start.warp.b;
    if (t.reference.ncc(aligned_image_, warp) < kMinStartNcc) continue;
    const AlignmentResult aligned =
        t.reference.align(aligned_image_, &warp, kMaxAlignmentIterations, kAlignmentTolerancePx);
    if (!aligned.converged || aligned.ncc < settings_.sudden_loss_ncc ||
        (warp.b - predicted).norm() > radius || !in_region(warp.b))
      continue;
    const auto same = std::find_if(found.begin(), found.end(), [&](const Place& f) {
      return (f.warp.b - warp.b).norm() < kSamePositionPx;
    });
    if (same == found.end())
      found.push_back({warp, start.young, aligned.ncc});
    else if (start.young >= 0)
      same->young = start.young;
  }
  return found;
}

FeatureTracker::Recognition FeatureTracker::recognise(const Track& t, const Place& place,
                                                      double radius) const {
  // The descriptor, taken where the track started, must agree; then no twin may lie around (the
  // costlier test, last).
  const Eigen::Matrix2d& A = place.warp.A;
  const double turned = std::atan2(A(1, 0) - A(0, 1), A(0, 0) + A(1, 1));
  const Descriptor now = describe(image_, point(place.warp.b), turned);
  if (!now.valid || !t.descriptor.valid ||
      hamming_distance(now, t.descriptor) > settings_.max_descriptor_distance)
    return Recognition::kNot;
  return repeated_nearby(t, place.warp,
                         std::max(kRepeatReach * radius,
                                  kRepeatMinReachPatches * (2 * t.reference.half_size() + 1)))
             ? Recognition::kAmongTwins
             : Recognition::kRecognised;
}

void FeatureTracker::reacquire(std::vector<cv::Point2f>* corners,
                               std::vector<cv::Point2f>* reacquired) {
  std::vector<bool> corner_used(corners->size(), false), young_ended(live_.size(), false);
  // Built for the first young lost track that needs it: most frames have none.
  std::optional<StepNeighbourhoods> neighbourhoods;
  std::deque<Track> still_lost;
  std::vector<Track> back;
  for (Track& t : lost_) {
    // A track seen too briefly to know its own image motion is looked for where its neighbours'
    // motion this frame puts it, for a few frames, or not at all: standing still, it would be
    // looked for where the camera's motion no longer leaves it (a lab track lost in its second
    // frame came back 116 px from its point, on a look-alike brick), and beyond a few frames its
    // neighbours' motion no longer holds for it (at 512 x 384, 3 of 10 such lab tracks came back
    // 1.6-7 px off after gaps of 4-10 frames).
    Eigen::Vector2d predicted = t.predicted(frame_);
    if (!t.moved_long_enough()) {
      Eigen::Vector2d step;
      if (frame_ - t.last_frame <= kYoungMaxGap && !neighbourhoods) neighbourhoods = live_steps();
      if (frame_ - t.last_frame > kYoungMaxGap ||
          !neighbourhoods->median_step(t.position, live_.size(), kMinNeighbours, &step)) {
        still_lost.push_back(std::move(t));
        continue;
      }
      predicted = t.position + (frame_ - t.last_frame) * step;
    }
    const double radius = settings_.reacquire_radius_px +
                          (frame_ - t.last_frame) * settings_.reacquire_radius_growth_px;
    const std::vector<Place> found = places_found(
        t, reacquisition_starts(t, predicted, radius, *corners, corner_used, young_ended),
        predicted, radius);
    const Recognition recognition =
        found.size() == 1 ? recognise(t, found[0], radius) : Recognition::kNot;
    // Among twins it is forgotten: repeated texture stays repeated as the camera moves, and each
    // later look would search it again (on the realistic lab, 214 of 240 searches found a twin,
    // for the same tracks up to 16 times: 60 % of the tracker's time). Where more than one place
    // was found, no twin search ran, and it stays lost.
    if (recognition == Recognition::kAmongTwins) {
      ++statistics_.forgotten_among_twins;
      continue;
    }
    if (recognition == Recognition::kNot) {
      still_lost.push_back(std::move(t));
      continue;
    }
    const Place& here = found[0];
    if (here.young >= 0) young_ended[here.young] = true;
    for (size_t c = 0; c < corners->size(); ++c)
      if ((vector((*corners)[c]) - here.warp.b).norm() < settings_.min_distance_px)
        corner_used[c] = true;
    t.position = here.warp.b;
    t.warp = here.warp;
    t.shape_step.setIdentity();
    t.ncc = here.ncc;
    if (frame_ - t.last_frame == 1) ++statistics_.reacquired_at_once;
    t.last_frame = frame_;
    t.recent.assign(1, t.position);
    t.velocity = Eigen::Vector2d::Zero();
    reacquired->push_back(point(t.position));
    back.push_back(std::move(t));
    ++statistics_.reacquired;
  }
  lost_.swap(still_lost);

  // A young track recognised as a lost one gives way to it.
  keep_live_tracks([&](size_t i) { return !young_ended[i]; });
  for (Track& t : back) live_.push_back(std::move(t));
  std::vector<cv::Point2f> unused;
  for (size_t c = 0; c < corners->size(); ++c)
    if (!corner_used[c]) unused.push_back((*corners)[c]);
  corners->swap(unused);
}

}  // namespace omnisfm::track
