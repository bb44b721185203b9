#pragma once
// Turns true points seen along a trajectory into the tracks a tracker would report: Gaussian noise,
// tracks that end when their point leaves the field of view or is hidden, and mistracks that slide
// to a wrong feature or drift.

#include <random>
#include <vector>

#include "omnisfm/sim/dataset.h"

namespace omnisfm::sim {

struct TrackSimulationOptions {
  double noise_px = 0.2;
  int num_mistracked = 0;       // how many points' tracks go wrong part way
  double border_px = 3.0;       // a point this close to the image edge is lost
  int min_track_length = 2;     // shorter visible runs are not reported
};

// Fills dataset->track_points, observations and outliers from `points` (world) seen by
// dataset->camera at dataset->world_from_cam, hidden by dataset->scene. Each maximal run of frames
// in which a point is visible becomes one track.
void simulate_tracks(const std::vector<Eigen::Vector3d>& points,
                     const TrackSimulationOptions& options, std::mt19937_64& rng, Dataset* dataset);

// `count` points on the ground (z = 0, x in [-2, 6] m, y in [-4, 4] m) that dataset's rig sees
// in every frame, drawn from rng, and their pixels in every frame with noise_px Gaussian noise:
// tracks that never end, for timing and testing the filter on settled points. Throws
// std::invalid_argument when too few of a thousand draws per point are seen in every frame.
std::vector<core::TrackObservation> steady_ground_tracks(const Dataset& dataset, int count,
                                                       double noise_px, std::mt19937_64& rng);

// The pixel of a world point seen from world_from_cam, or false when it does not project or lies
// within border_px of the image's edge; with `reflection`, also where it is reflected.
bool visible_pixel(const camera::CatadioptricCamera& camera, const Eigen::Isometry3d& world_from_cam,
                   const Eigen::Vector3d& point_W, Eigen::Vector2d* pixel, double border_px = 0.0,
                   camera::Reflection* reflection = nullptr);

// The true pixel of a world point at a frame, or false when the rig cannot see it (off the image,
// or hidden by the dataset's scene).
bool true_pixel(const Dataset& dataset, int frame, const Eigen::Vector3d& point_W,
                Eigen::Vector2d* pixel, double border_px = 0.0);

// The scene point a pixel of a frame sees (true_pixel's inverse): where its reflected ray first
// meets the scene, within 10 km. False where the pixel has no ray or the ray meets nothing (the
// sky). *hit, when given, tells what it met.
bool scene_point(const Dataset& dataset, int frame, const Eigen::Vector2d& pixel,
                 Eigen::Vector3d* point_W, SceneHit* hit = nullptr);

// A standard normal deviate; the same on every platform for the same generator state.
double standard_normal(std::mt19937_64& rng);
// Independent standard normal deviates, drawn last coordinate first (the order the datasets were
// first made in). Eigen::Vector2d(standard_normal(rng), standard_normal(rng)) would leave the
// order to the compiler, and a seed's dataset would differ from one compiler to another.
Eigen::Vector2d standard_normal_2d(std::mt19937_64& rng);
Eigen::Vector3d standard_normal_3d(std::mt19937_64& rng);
double uniform(std::mt19937_64& rng, double lo, double hi);

}  // namespace omnisfm::sim
