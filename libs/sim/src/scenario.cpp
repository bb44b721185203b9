#include "omnisfm/sim/scenario.h"

#include <cmath>
#include <stdexcept>

#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/procedural_texture.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/sim/trajectories.h"

namespace omnisfm::sim {
namespace {

constexpr int kWall = kWallTexture, kFloor = kFloorTexture, kCeiling = kCeilingTexture,
              kBox = kBoxTexture, kGround = kGroundTexture;

// The inside of a room: floor, ceiling and four walls.
void add_room(Scene* scene, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d size = hi - lo;
  const Eigen::Vector3d ex(size.x(), 0, 0), ey(0, size.y(), 0), ez(0, 0, size.z());
  scene->add_quad({lo, ex, ey, kFloor});
  scene->add_quad({lo + ez, ex, ey, kCeiling});
  scene->add_quad({lo, ex, ez, kWall});
  scene->add_quad({lo + ey, ex, ez, kWall});
  scene->add_quad({lo, ey, ez, kWall});
  scene->add_quad({lo + ex, ey, ez, kWall});
}

// A point on a random face of a box other than its bottom.
Eigen::Vector3d point_on_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                             std::mt19937_64& rng) {
  // Each draw on a line of its own, last coordinate first: arguments have no order of evaluation.
  const double z = uniform(rng, lo.z(), hi.z());
  const double y = uniform(rng, lo.y(), hi.y());
  const double x = uniform(rng, lo.x(), hi.x());
  Eigen::Vector3d p(x, y, z);
  const int face = static_cast<int>(uniform(rng, 0, 5));
  if (face == 4) p.z() = hi.z();
  else if (face < 2) p.x() = face == 0 ? lo.x() : hi.x();
  else p.y() = face == 2 ? lo.y() : hi.y();
  return p;
}

// Fraction of the frames in which the rig sees a point.
double visible_fraction(const Dataset& d, const Eigen::Vector3d& point) {
  int seen = 0;
  Eigen::Vector2d pixel;
  for (size_t f = 0; f < d.world_from_cam.size(); ++f)
    seen += true_pixel(d, static_cast<int>(f), point, &pixel, 3.0);
  return static_cast<double>(seen) / d.world_from_cam.size();
}

// Draws candidates until `count` are seen in at least `min_fraction` of the frames.
template <typename Draw>
std::vector<Eigen::Vector3d> well_seen_points(const Dataset& d, int count, double min_fraction,
                                              Draw draw) {
  std::vector<Eigen::Vector3d> points;
  for (int tries = 0; tries < 10000 && static_cast<int>(points.size()) < count; ++tries) {
    const Eigen::Vector3d p = draw();
    if (visible_fraction(d, p) >= min_fraction) points.push_back(p);
  }
  if (static_cast<int>(points.size()) < count)
    throw std::runtime_error("simulate: the scene cannot show enough points");
  return points;
}

std::vector<double> timestamps(size_t frames, double period) {
  std::vector<double> t(frames);
  for (size_t i = 0; i < frames; ++i) t[i] = period * i;
  return t;
}

Dataset lab(const SimulationOptions& o, std::mt19937_64& rng) {
  Dataset d{"lab", default_rig(o.image_width, o.image_height), {}, {}, {}, {}, {}, {}, {}, {}};
  d.world_from_cam = lab_trajectory(1.0);
  d.timestamps = timestamps(d.world_from_cam.size(), 1.0);
  const Eigen::Vector3d lo(-1.6, -1.9, 0.0), hi(3.6, 2.9, 3.0);
  add_room(&d.scene, lo, hi);

  // 44 targets: 8 on each wall between 1.3 and 2.8 m, 12 on the ceiling; painted discs 1 mm
  // proud of their surface.
  std::vector<Eigen::Vector3d> targets;
  std::vector<Eigen::Vector3d> normals;
  auto jitter = [&](double a) { return a + uniform(rng, -0.15, 0.15); };
  for (int wall = 0; wall < 4; ++wall)
    for (int i = 0; i < 8; ++i) {
      const double along = (i + 0.5) / 8.0, height = i % 2 == 0 ? jitter(1.6) : jitter(2.4);
      Eigen::Vector3d p, n;
      switch (wall) {
        case 0: p << lo.x() + along * (hi.x() - lo.x()), lo.y(), height; n << 0, 1, 0; break;
        case 1: p << hi.x(), lo.y() + along * (hi.y() - lo.y()), height; n << -1, 0, 0; break;
        case 2: p << hi.x() - along * (hi.x() - lo.x()), hi.y(), height; n << 0, -1, 0; break;
        default: p << lo.x(), hi.y() - along * (hi.y() - lo.y()), height; n << 1, 0, 0; break;
      }
      p.head<2>() += n.head<2>().unitOrthogonal() * uniform(rng, -0.1, 0.1);
      targets.push_back(p + 0.001 * n);
      normals.push_back(n);
    }
  for (int i = 0; i < 12; ++i) {
    const double dy = uniform(rng, -0.2, 0.2);
    const double dx = uniform(rng, -0.2, 0.2);
    const Eigen::Vector3d p(lo.x() + (0.15 + 0.7 * (i % 4) / 3.0) * (hi.x() - lo.x()) + dx,
                            lo.y() + (0.2 + 0.6 * (i / 4) / 2.0) * (hi.y() - lo.y()) + dy,
                            hi.z() - 0.001);
    targets.push_back(p);
    normals.emplace_back(0, 0, -1);
  }
  for (size_t i = 0; i < targets.size(); ++i)
    d.scene.add_marker({targets[i], normals[i], 0.05, static_cast<int>(i)});

  TrackSimulationOptions tracking;
  tracking.noise_px = o.tracking_noise_px;
  simulate_tracks(targets, tracking, rng, &d);

  // The survey, and the calibration images (the corners of the U) as an operator would mark them.
  for (const auto& t : targets)
    d.surveyed_targets.push_back(
        t + o.survey_error_m * standard_normal_3d(rng));
  for (const int image : {0, 10, 30, 40})  // the corners of the U
    for (size_t i = 0; i < targets.size(); ++i) {
      Eigen::Vector2d pixel;
      if (!true_pixel(d, image, targets[i], &pixel, 3.0)) continue;
      pixel += o.tracking_noise_px * standard_normal_2d(rng);
      d.target_observations.push_back({image, static_cast<int>(i), pixel});
    }
  return d;
}

Dataset crane(const SimulationOptions& o, std::mt19937_64& rng) {
  Dataset d{"crane", default_rig(o.image_width, o.image_height), {}, {}, {}, {}, {}, {}, {}, {}};
  d.world_from_cam = crane_trajectory(0.6, 2.2);
  d.timestamps = timestamps(d.world_from_cam.size(), 0.5);
  add_room(&d.scene, {-7, -7, 0}, {7, 7, 6});
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes;
  for (int i = 0; i < 6; ++i) {
    const double a = 2 * M_PI * i / 6 + uniform(rng, -0.3, 0.3), r = uniform(rng, 1.8, 3.2);
    const Eigen::Vector3d centre(r * std::cos(a), r * std::sin(a), 0);
    const double half_y = uniform(rng, 0.2, 0.4);
    const double half_x = uniform(rng, 0.2, 0.4);
    const Eigen::Vector3d half(half_x, half_y, 0);
    const Eigen::Vector3d lo = centre - half, hi = centre + half + Eigen::Vector3d(0, 0, uniform(rng, 0.3, 0.8));
    d.scene.add_box(lo, hi, kBox);
    boxes.emplace_back(lo, hi);
  }
  const auto points = well_seen_points(d, 32, 0.8, [&] {
    if (uniform(rng, 0, 1) < 0.3) {
      const auto& b = boxes[static_cast<size_t>(uniform(rng, 0, boxes.size()))];
      return point_on_box(b.first, b.second, rng);
    }
    const double a = uniform(rng, -M_PI, M_PI), r = uniform(rng, 0.8, 3.5);
    return Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0);
  });
  TrackSimulationOptions tracking;
  tracking.noise_px = o.tracking_noise_px;
  tracking.num_mistracked = 10;
  simulate_tracks(points, tracking, rng, &d);
  return d;
}

Dataset rover(const SimulationOptions& o, std::mt19937_64& rng) {
  Dataset d{"rover", default_rig(o.image_width, o.image_height), {}, {}, {}, {}, {}, {}, {}, {}};
  d.world_from_cam = rover_trajectory(0.6);
  d.timestamps = timestamps(d.world_from_cam.size(), 0.5);
  // A courtyard: outdoor ground and four walls, open to the sky.
  const Eigen::Vector3d lo(-4, -5, 0), hi(9, 5, 3);
  add_room(&d.scene, lo, hi);
  Scene courtyard;
  for (TexturedQuad quad : d.scene.quads()) {
    if (quad.texture == kCeiling) continue;
    if (quad.texture == kFloor) quad.texture = kGround;
    courtyard.add_quad(quad);
  }
  d.scene = courtyard;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> boxes;
  const Eigen::Vector2d box_centres[] = {{1.0, 2.2}, {3.0, -2.0}, {5.5, 2.5}, {-1.5, -2.5}, {6.5, -1.5}};
  for (const auto& c : box_centres) {
    const double half_y = uniform(rng, 0.3, 0.6);
    const double half_x = uniform(rng, 0.3, 0.6);
    const Eigen::Vector3d half(half_x, half_y, 0);
    const Eigen::Vector3d centre(c.x(), c.y(), 0);
    const Eigen::Vector3d blo = centre - half, bhi = centre + half + Eigen::Vector3d(0, 0, uniform(rng, 0.5, 1.2));
    d.scene.add_box(blo, bhi, kBox);
    boxes.emplace_back(blo, bhi);
  }
  const auto points = well_seen_points(d, 112, 0.5, [&]() -> Eigen::Vector3d {
    const double kind = uniform(rng, 0, 1);
    if (kind < 0.15) {
      const auto& b = boxes[static_cast<size_t>(uniform(rng, 0, boxes.size()))];
      return point_on_box(b.first, b.second, rng);
    }
    if (kind < 0.4) {
      // On a wall, low enough for the rig's view (at most 10 degrees above the horizon).
      const int wall = static_cast<int>(uniform(rng, 0, 4));
      const double h = uniform(rng, 0.1, 1.2);
      if (wall == 0) return {uniform(rng, lo.x(), hi.x()), lo.y(), h};
      if (wall == 1) return {uniform(rng, lo.x(), hi.x()), hi.y(), h};
      if (wall == 2) return {lo.x(), uniform(rng, lo.y(), hi.y()), h};
      return {hi.x(), uniform(rng, lo.y(), hi.y()), h};
    }
    return {uniform(rng, -1.5, 5.5), uniform(rng, -3.5, 3.5), 0.0};
  });
  TrackSimulationOptions tracking;
  tracking.noise_px = o.tracking_noise_px;
  tracking.num_mistracked = 7;
  simulate_tracks(points, tracking, rng, &d);
  return d;
}

}  // namespace

bool is_known_scenario(const std::string& name) {
  return name == "lab" || name == "crane" || name == "rover" || name == "drive";
}

camera::CatadioptricCamera default_rig(int image_width, int image_height) {
  const double scale = image_width / 1024.0;
  camera::PinholeIntrinsics k;
  k.fx = k.fy = 800 * scale;
  k.cx = (image_width - 1) / 2.0;
  k.cy = (image_height - 1) / 2.0;
  return camera::CatadioptricCamera(
      std::make_unique<camera::PinholeCamera>(k),
      std::make_unique<camera::EquiangularProfile>(5.0, 0.05, 0.02, 0.35),
      camera::MirrorPose{0.004, -0.003, 0.003, -0.002, 0.002}, image_width, image_height);
}

Dataset simulate(const SimulationOptions& options) {
  if (!is_known_scenario(options.scenario))
    throw std::invalid_argument("unknown scenario '" + options.scenario +
                                "' (expected lab, crane, rover or drive)");
  if (!(options.tracking_noise_px >= 0) || !std::isfinite(options.tracking_noise_px))
    throw std::invalid_argument("the tracking noise must be a finite number >= 0");
  if (!(options.survey_error_m >= 0) || !std::isfinite(options.survey_error_m))
    throw std::invalid_argument("the survey error must be a finite number >= 0");
  if (options.image_width < 64 || options.image_height < 48 ||
      options.image_width > 16384 || options.image_height > 16384)
    throw std::invalid_argument("the image size must be between 64x48 and 16384x16384");
  // The default rig's rim images 292 px from the centre at 1024 px wide.
  if (292.0 * options.image_width / 1024.0 > (options.image_height - 1) / 2.0)
    throw std::invalid_argument("the image is too wide for the mirror's circle (height >= 0.58 width)");
  if (options.scenario == "drive") {
    if (options.frames < 2) throw std::invalid_argument("a drive needs at least 2 frames");
    return long_drive(options.frames, options.tracking_noise_px, options.seed,
                      default_rig(options.image_width, options.image_height));
  }
  std::mt19937_64 rng(options.seed);
  if (options.scenario == "lab") return lab(options, rng);
  if (options.scenario == "crane") return crane(options, rng);
  return rover(options, rng);
}

}  // namespace omnisfm::sim
