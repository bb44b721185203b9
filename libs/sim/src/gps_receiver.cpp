#include "omnisfm/sim/gps_receiver.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/track_simulator.h"

namespace omnisfm::sim {
namespace {

// Keeps the receiver's noise independent of the tracks' and the dead reckoning's.
constexpr std::uint64_t kGpsStream = 0x6e55f1c5;

void check(const Dataset& d, const GpsOptions& o) {
  if (d.world_from_cam.size() < 2 || d.timestamps.size() != d.world_from_cam.size())
    throw std::invalid_argument("GPS simulation needs at least two frames with timestamps");
  for (size_t k = 1; k < d.timestamps.size(); ++k)
    if (!(d.timestamps[k] > d.timestamps[k - 1]))
      throw std::invalid_argument("GPS simulation needs increasing timestamps");
  if (!(o.rate_hz > 0) || !std::isfinite(o.rate_hz))
    throw std::invalid_argument("the GPS rate must be positive");
  if (!(o.horizontal_sigma >= 0) || !(o.vertical_sigma >= 0) ||
      !std::isfinite(o.horizontal_sigma) || !std::isfinite(o.vertical_sigma))
    throw std::invalid_argument("GPS noise must be finite and not negative");
}

}  // namespace

GpsTrack simulate_gps(const Dataset& dataset, const GpsOptions& options) {
  check(dataset, options);
  GpsTrack track;
  track.enu_from_world.linear() =
      Eigen::AngleAxisd(options.world_heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  track.enu_from_world.translation() = options.world_origin_enu;
  track.body_from_cam = body_from_cam(dataset);
  track.antenna_in_body = options.antenna_in_body;
  track.latitude_deg = options.latitude_deg;
  track.longitude_deg = options.longitude_deg;
  track.height_m = options.height_m;
  track.horizontal_sigma = options.horizontal_sigma;
  track.vertical_sigma = options.vertical_sigma;

  std::mt19937_64 rng(options.seed ^ kGpsStream);
  const Eigen::Isometry3d cam_from_body = track.body_from_cam.inverse();
  const double t0 = dataset.timestamps.front(), t1 = dataset.timestamps.back();
  for (long i = 0;; ++i) {
    const double t = t0 + static_cast<double>(i) / options.rate_hz;
    if (t > t1 + 1e-9) break;
    const Eigen::Isometry3d world_from_body = interpolate_pose(dataset, t) * cam_from_body;
    GpsReading fix;
    fix.timestamp = t;
    fix.enu = track.enu_from_world * (world_from_body * options.antenna_in_body);
    fix.enu.x() += options.horizontal_sigma * standard_normal(rng);
    fix.enu.y() += options.horizontal_sigma * standard_normal(rng);
    fix.enu.z() += options.vertical_sigma * standard_normal(rng);
    track.fixes.push_back(fix);
  }
  return track;
}

}  // namespace omnisfm::sim
