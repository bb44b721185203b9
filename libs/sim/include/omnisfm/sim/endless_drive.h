#pragma once
// A rover drive of any length, made as it goes: the rig 3 cm further each frame (one frame every
// half second, 6 cm/s) along an S that repeats every 300 frames, one ground point per frame a
// little to the side of the path, seen from the frames within 15 of its own that image it (tracks
// about 30 frames long), pixels with Gaussian noise. Only the frames and points that the coming
// frames need are held, so a drive of any length takes constant memory, and the same seed gives the
// same drive however far it is read. The motion is planar with the camera's z axis up, so the
// simulated odometry and gyro (dead_reckoning.h) apply to it.

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <random>
#include <vector>

#include "omnisfm/sim/dataset.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sim {

struct DriveFrame {
  int index = 0;
  double timestamp = 0;  // seconds
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  std::vector<TrackObservation> observations;  // sorted by track
};

class EndlessDrive {
 public:
  static constexpr double kFramePeriod = 0.5;  // seconds
  static constexpr double kStep = 0.03;        // metres per frame

  EndlessDrive(const camera::CatadioptricCamera& camera, double pixel_noise, std::uint64_t seed);

  const camera::CatadioptricCamera& camera() const { return camera_; }
  // The next frame: 0, 1, 2, ...
  DriveFrame next();
  // The true world point of a track seen in the last frame returned or in the 15 after it (track
  // ids are handed out in order, one per frame); throws std::out_of_range for any other.
  const Eigen::Vector3d& true_point(int track) const;

 private:
  struct Track {
    Eigen::Vector3d point;
    std::vector<TrackObservation> seen;  // by frame
  };
  // world_from_cam of a frame not yet dropped, extending the path as far as needed.
  const Eigen::Isometry3d& pose(int frame);
  void add_track();

  camera::CatadioptricCamera camera_;
  double pixel_noise_;
  std::mt19937_64 rng_;
  std::deque<Eigen::Isometry3d> poses_;  // frames first_pose_ on
  int first_pose_ = 0;
  Eigen::Vector3d next_position_{0, 0, 0.6};
  std::deque<Track> tracks_;  // tracks first_track_ on
  int first_track_ = 0;
  int next_frame_ = 0;
};

// The first `frames` frames of an endless drive as a dataset: timestamps, world_from_cam,
// track_points (every track id seen) and observations (those of tracks seen at least twice); no
// outliers and no scene.
Dataset long_drive(int frames, double pixel_noise, std::uint64_t seed,
                   const camera::CatadioptricCamera& camera = default_rig(1024, 768));

}  // namespace omnisfm::sim
