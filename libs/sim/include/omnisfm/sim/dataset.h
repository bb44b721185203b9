#pragma once
// A simulated dataset with its ground truth, as `omnisfm simulate` writes it (DESIGN.md section 3).

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/core/track_observation.h"
#include "omnisfm/sim/scene.h"

namespace omnisfm::sim {

// One tracked pixel, as tracks.vnl holds it.
using TrackObservation = core::TrackObservation;

// A track that goes wrong (the tracker slides to another feature or drifts) from `frame` on.
struct OutlierTruth {
  int track = 0;
  int frame = 0;
};

struct TargetObservation {
  int image = 0;
  int target = 0;
  Eigen::Vector2d pixel{0, 0};
};

struct Dataset {
  std::string scenario;
  camera::CatadioptricCamera camera;
  std::vector<double> timestamps;                // per frame, seconds
  std::vector<Eigen::Isometry3d> world_from_cam;  // per frame
  std::vector<Eigen::Vector3d> track_points;     // world position of each track id's true point
  std::vector<TrackObservation> observations;    // sorted by frame, then track
  std::vector<OutlierTruth> outliers;            // sorted by track
  Scene scene;
  // Lab only: surveyed targets (as surveyed, with survey error) and the calibration images' views.
  std::vector<Eigen::Vector3d> surveyed_targets;
  std::vector<TargetObservation> target_observations;
};

}  // namespace omnisfm::sim
