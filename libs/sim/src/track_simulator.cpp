#include "omnisfm/sim/track_simulator.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace omnisfm::sim {

double uniform(std::mt19937_64& rng, double lo, double hi) {
  // 53 random bits -> [0, 1): the same on every platform, unlike std::uniform_real_distribution.
  const double unit = static_cast<double>(rng() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * unit;
}

double standard_normal(std::mt19937_64& rng) {
  // Box-Muller; 1 - u keeps the logarithm finite.
  const double u = uniform(rng, 0, 1), v = uniform(rng, 0, 1);
  return std::sqrt(-2 * std::log(1 - u)) * std::cos(2 * M_PI * v);
}

Eigen::Vector2d standard_normal_2d(std::mt19937_64& rng) {
  const double y = standard_normal(rng);
  const double x = standard_normal(rng);
  return {x, y};
}

Eigen::Vector3d standard_normal_3d(std::mt19937_64& rng) {
  const double z = standard_normal(rng);
  const double y = standard_normal(rng);
  const double x = standard_normal(rng);
  return {x, y, z};
}

std::vector<core::TrackObservation> steady_ground_tracks(const Dataset& dataset, int count,
                                                       double noise_px, std::mt19937_64& rng) {
  // A rig that sees too little of the ground would otherwise be searched for ever.
  const long max_draws = 1000L * std::max(count, 1);
  std::vector<Eigen::Vector3d> points;
  for (long draw = 0; static_cast<int>(points.size()) < count; ++draw) {
    if (draw == max_draws)
      throw std::invalid_argument("steady_ground_tracks: the rig sees too little of the ground "
                                  "in every frame for " + std::to_string(count) + " points");
    const double y = uniform(rng, -4, 4);  // before x: arguments have no order of evaluation
    const double x = uniform(rng, -2, 6);
    const Eigen::Vector3d p(x, y, 0.0);
    Eigen::Vector2d pixel;
    bool always = true;
    for (size_t f = 0; f < dataset.world_from_cam.size() && always; ++f)
      always = true_pixel(dataset, static_cast<int>(f), p, &pixel, 3.0);
    if (always) points.push_back(p);
  }
  std::vector<core::TrackObservation> tracks;
  for (size_t f = 0; f < dataset.world_from_cam.size(); ++f)
    for (int i = 0; i < count; ++i) {
      Eigen::Vector2d pixel;
      true_pixel(dataset, static_cast<int>(f), points[i], &pixel);
      pixel += noise_px * standard_normal_2d(rng);
      tracks.push_back({static_cast<int>(f), i, pixel});
    }
  return tracks;
}

bool visible_pixel(const camera::CatadioptricCamera& camera, const Eigen::Isometry3d& world_from_cam,
                   const Eigen::Vector3d& point_W, Eigen::Vector2d* pixel, double border_px,
                   camera::Reflection* reflection) {
  if (!camera.project(world_from_cam.inverse() * point_W, pixel, nullptr, nullptr, reflection))
    return false;
  return pixel->x() >= border_px && pixel->y() >= border_px &&
         pixel->x() <= camera.image_width() - 1 - border_px &&
         pixel->y() <= camera.image_height() - 1 - border_px;
}

bool true_pixel(const Dataset& dataset, int frame, const Eigen::Vector3d& point_W,
                Eigen::Vector2d* pixel, double border_px) {
  camera::Reflection reflection;
  if (!visible_pixel(dataset.camera, dataset.world_from_cam[frame], point_W, pixel, border_px,
                     &reflection))
    return false;
  // The reflected ray from the mirror to the point must be clear of the scene.
  const Eigen::Vector3d mirror_W = dataset.world_from_cam[frame] * reflection.point_C;
  return dataset.scene.visible(mirror_W, point_W);
}

// Farther than any surface of a scenario's scene: a ray that meets nothing within it sees none.
constexpr double kFarthestSurfaceM = 1e4;

bool scene_point(const Dataset& dataset, int frame, const Eigen::Vector2d& pixel,
                 Eigen::Vector3d* point_W, SceneHit* hit) {
  Eigen::Vector3d origin, direction;
  if (!dataset.camera.unproject(pixel, &origin, &direction)) return false;
  const Eigen::Isometry3d& world_from_cam = dataset.world_from_cam[frame];
  const Eigen::Vector3d origin_W = world_from_cam * origin;
  const Eigen::Vector3d direction_W = world_from_cam.linear() * direction;
  SceneHit met;
  if (!dataset.scene.intersect(origin_W, direction_W, kFarthestSurfaceM, &met)) return false;
  *point_W = origin_W + met.distance * direction_W;
  if (hit) *hit = met;
  return true;
}

namespace {

struct Run {
  int point, first, last;  // frames first..last inclusive
};

// How a mistracked track goes wrong.
struct Mistrack {
  int start_frame;
  bool slides;                     // to a wrong feature (else drifts)
  Eigen::Vector3d wrong_point_W;   // slides: the feature it follows instead
  Eigen::Vector2d drift_per_frame; // drifts: pixels per frame
};

}  // namespace

void simulate_tracks(const std::vector<Eigen::Vector3d>& points,
                     const TrackSimulationOptions& options, std::mt19937_64& rng,
                     Dataset* dataset) {
  const int num_frames = static_cast<int>(dataset->world_from_cam.size());
  // Visibility of every point in every frame.
  std::vector<std::vector<Eigen::Vector2d>> pixels(points.size(),
                                                   std::vector<Eigen::Vector2d>(num_frames));
  std::vector<Run> runs;
  for (size_t p = 0; p < points.size(); ++p) {
    int start = -1;
    for (int f = 0; f <= num_frames; ++f) {
      const bool visible =
          f < num_frames && true_pixel(*dataset, f, points[p], &pixels[p][f], options.border_px);
      if (visible && start < 0) start = f;
      if (!visible && start >= 0) {
        if (f - start >= options.min_track_length) runs.push_back({static_cast<int>(p), start, f - 1});
        start = -1;
      }
    }
  }

  // Mistracks: among the longest runs of distinct points, so that each has frames to go wrong in.
  std::vector<size_t> order(runs.size());
  std::iota(order.begin(), order.end(), 0);
  std::vector<size_t> candidates;
  for (size_t r : order)
    if (runs[r].last - runs[r].first >= 8) candidates.push_back(r);
  for (size_t i = candidates.size(); i > 1; --i)
    std::swap(candidates[i - 1], candidates[static_cast<size_t>(uniform(rng, 0, i))]);
  std::vector<int> mistracked_points;
  std::vector<std::pair<size_t, Mistrack>> mistracks;
  for (size_t r : candidates) {
    if (static_cast<int>(mistracks.size()) >= options.num_mistracked) break;
    const Run& run = runs[r];
    if (std::find(mistracked_points.begin(), mistracked_points.end(), run.point) !=
        mistracked_points.end())
      continue;
    const int length = run.last - run.first + 1;
    Mistrack m;
    m.start_frame = run.first + static_cast<int>(uniform(rng, 0.3, 0.7) * length);
    m.slides = mistracks.size() % 2 == 0;
    // A neighbouring feature 10-25 cm away, or a drift of 0.3-0.8 px per frame.
    if (m.slides) {
      bool found = false;
      for (int attempt = 0; attempt < 50 && !found; ++attempt) {
        const Eigen::Vector3d offset = standard_normal_3d(rng);
        m.wrong_point_W = points[run.point] + offset.normalized() * uniform(rng, 0.10, 0.25);
        // It must stay in view a while and jump visibly in the image: a feature hiding behind
        // the true one along the same ray would be no mistrack at all.
        Eigen::Vector2d wrong;
        found = true_pixel(*dataset, m.start_frame, m.wrong_point_W, &wrong, options.border_px) &&
                (wrong - pixels[run.point][m.start_frame]).norm() >= 3.0;
        for (int f = m.start_frame + 1; f < std::min(m.start_frame + 3, run.last + 1) && found; ++f)
          found = true_pixel(*dataset, f, m.wrong_point_W, &wrong, options.border_px);
      }
      if (!found) continue;
    }
    const double angle = uniform(rng, -M_PI, M_PI);
    m.drift_per_frame = uniform(rng, 0.3, 0.8) * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    mistracked_points.push_back(run.point);
    mistracks.emplace_back(r, m);
  }

  // Number the tracks in order of first frame, then point.
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::tie(runs[a].first, runs[a].point) < std::tie(runs[b].first, runs[b].point);
  });
  dataset->track_points.clear();
  dataset->observations.clear();
  dataset->outliers.clear();
  for (size_t id = 0; id < order.size(); ++id) {
    const size_t r = order[id];
    const Run& run = runs[r];
    const Mistrack* mistrack = nullptr;
    for (const auto& [mr, m] : mistracks)
      if (mr == r) mistrack = &m;
    const int track = static_cast<int>(id);
    dataset->track_points.push_back(points[run.point]);
    for (int f = run.first; f <= run.last; ++f) {
      Eigen::Vector2d pixel = pixels[run.point][f];
      if (mistrack && f >= mistrack->start_frame) {
        if (mistrack->slides) {
          // Following the wrong feature; the track ends when that one is lost.
          if (!true_pixel(*dataset, f, mistrack->wrong_point_W, &pixel, options.border_px)) break;
        } else {
          pixel += mistrack->drift_per_frame * (f - mistrack->start_frame + 1);
        }
      }
      pixel += options.noise_px * standard_normal_2d(rng);
      dataset->observations.push_back({f, track, pixel});
    }
    if (mistrack) dataset->outliers.push_back({track, mistrack->start_frame});
  }
  std::stable_sort(dataset->observations.begin(), dataset->observations.end(),
                   [](const TrackObservation& a, const TrackObservation& b) {
                     return std::tie(a.frame, a.track) < std::tie(b.frame, b.track);
                   });
  std::sort(dataset->outliers.begin(), dataset->outliers.end(),
            [](const OutlierTruth& a, const OutlierTruth& b) { return a.track < b.track; });
}

}  // namespace omnisfm::sim
