#include "omnisfm/sim/endless_drive.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sim {
namespace {

// A track is seen from the frames within this many of its own.
constexpr int kReach = 15;
constexpr int kTurnPeriod = 300;  // frames
constexpr double kBorderPx = 3.0;

}  // namespace

EndlessDrive::EndlessDrive(const camera::CatadioptricCamera& camera, double pixel_noise,
                           std::uint64_t seed)
    : camera_(camera), pixel_noise_(pixel_noise), rng_(seed) {
  if (!(pixel_noise >= 0) || !std::isfinite(pixel_noise))
    throw std::invalid_argument("the tracking noise must be a finite number >= 0");
}

const Eigen::Isometry3d& EndlessDrive::pose(int frame) {
  while (first_pose_ + static_cast<int>(poses_.size()) <= frame) {
    const int i = first_pose_ + static_cast<int>(poses_.size());
    const double heading = 0.7 * std::sin(2 * M_PI * i / kTurnPeriod);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = next_position_;
    poses_.push_back(T);
    next_position_ += kStep * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
  }
  return poses_.at(frame - first_pose_);
}

void EndlessDrive::add_track() {
  const int track = first_track_ + static_cast<int>(tracks_.size());
  const int first = std::max(0, track - kReach), end = track + kReach;
  // A ground point beside the path, drawn again until nearly all of its frames see it: a track
  // that is not seen for long leaves its depth free, which no real tracker would keep.
  Track t;
  for (int draw = 0;; ++draw) {
    if (draw == 1000)
      throw std::runtime_error("EndlessDrive: the rig does not see the ground beside its path");
    const Eigen::Isometry3d& T = pose(track);
    // One draw per statement: operands and arguments have no order of evaluation.
    const double distance = uniform(rng_, 0.8, 2.0);
    const double side = uniform(rng_, 0, 1) < 0.5 ? -distance : distance;
    t.point = T * Eigen::Vector3d(uniform(rng_, -0.5, 0.5), side, 0);
    t.point.z() = 0;
    t.seen.clear();
    for (int f = first; f < end; ++f) {
      Eigen::Vector2d pixel;
      if (!visible_pixel(camera_, pose(f), t.point, &pixel, kBorderPx)) continue;
      pixel += pixel_noise_ * standard_normal_2d(rng_);
      t.seen.push_back({f, track, pixel});
    }
    if (5 * static_cast<int>(t.seen.size()) >= 4 * (end - first)) break;
  }
  tracks_.push_back(std::move(t));
}

DriveFrame EndlessDrive::next() {
  const int f = next_frame_++;
  // Frame f sees the tracks f - kReach + 1 .. f + kReach.
  while (first_track_ < f - kReach + 1) {
    tracks_.pop_front();
    ++first_track_;
  }
  while (first_track_ + static_cast<int>(tracks_.size()) <= f + kReach) add_track();
  DriveFrame frame;
  frame.index = f;
  frame.timestamp = kFramePeriod * f;
  frame.world_from_cam = pose(f);
  for (const Track& t : tracks_)
    for (const TrackObservation& o : t.seen)
      if (o.frame == f) frame.observations.push_back(o);
  // No later track needs a frame before this one.
  while (first_pose_ < f) {
    poses_.pop_front();
    ++first_pose_;
  }
  return frame;
}

const Eigen::Vector3d& EndlessDrive::true_point(int track) const {
  const int k = track - first_track_;
  if (k < 0 || k >= static_cast<int>(tracks_.size()))
    throw std::out_of_range("EndlessDrive: track " + std::to_string(track) +
                            " is not near the current frame");
  return tracks_[k].point;
}

Dataset long_drive(int frames, double pixel_noise, std::uint64_t seed,
                   const camera::CatadioptricCamera& camera) {
  Dataset d{"drive", camera, {}, {}, {}, {}, {}, {}, {}, {}};
  EndlessDrive drive(d.camera, pixel_noise, seed);
  for (int i = 0; i < frames; ++i) {
    DriveFrame frame = drive.next();
    d.timestamps.push_back(frame.timestamp);
    d.world_from_cam.push_back(frame.world_from_cam);
    for (const TrackObservation& o : frame.observations)
      while (static_cast<int>(d.track_points.size()) <= o.track)
        d.track_points.push_back(drive.true_point(static_cast<int>(d.track_points.size())));
    d.observations.insert(d.observations.end(), frame.observations.begin(),
                          frame.observations.end());
  }
  // The drive's end cuts the last tracks short: one seen once is no track.
  std::vector<int> seen(d.track_points.size(), 0);
  for (const TrackObservation& o : d.observations) ++seen[o.track];
  d.observations.erase(std::remove_if(d.observations.begin(), d.observations.end(),
                                      [&](const TrackObservation& o) { return seen[o.track] < 2; }),
                       d.observations.end());
  return d;
}

}  // namespace omnisfm::sim
