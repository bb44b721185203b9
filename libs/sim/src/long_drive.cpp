#include "omnisfm/sim/long_drive.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sim {

Dataset long_drive(int images, double pixel_noise, std::uint64_t seed) {
  Dataset d{"drive", default_rig(1024, 768), {}, {}, {}, {}, {}, {}, {}, {}};
  Eigen::Vector3d position(0, 0, 0.6);
  for (int i = 0; i < images; ++i) {
    const double heading = 0.7 * std::sin(2 * M_PI * i / 300.0);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() = position;
    d.world_from_cam.push_back(T);
    position += 0.03 * Eigen::Vector3d(std::cos(heading), std::sin(heading), 0);
  }
  std::mt19937_64 rng(seed);
  for (int track = 0; track < images; ++track) {
    // A ground point beside the path, drawn again until nearly all of its 30 frames see it: a
    // track that is not seen for long leaves its depth free, which no real tracker would keep.
    const int first = std::max(0, track - 15), end = std::min(images, track + 15);
    Eigen::Vector3d point;
    std::vector<TrackObservation> seen;
    do {
      const Eigen::Isometry3d& T = d.world_from_cam[track];
      const double side = uniform(rng, 0.8, 2.0) * (uniform(rng, 0, 1) < 0.5 ? -1 : 1);
      point = T * Eigen::Vector3d(uniform(rng, -0.5, 0.5), side, 0);
      point.z() = 0;
      seen.clear();
      for (int f = first; f < end; ++f) {
        Eigen::Vector2d pixel;
        if (!true_pixel(d, f, point, &pixel, 3.0)) continue;
        pixel += pixel_noise * Eigen::Vector2d(standard_normal(rng), standard_normal(rng));
        seen.push_back({f, track, pixel});
      }
    } while (5 * static_cast<int>(seen.size()) < 4 * (end - first));
    d.track_points.push_back(point);
    d.observations.insert(d.observations.end(), seen.begin(), seen.end());
  }
  std::stable_sort(d.observations.begin(), d.observations.end(),
                   [](const TrackObservation& a, const TrackObservation& b) {
                     return a.frame < b.frame;
                   });
  return d;
}

}  // namespace omnisfm::sim
