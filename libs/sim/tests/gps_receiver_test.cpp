// Simulated GPS: exact antenna positions without noise, and the stated noise otherwise.

#include "omnisfm/sim/gps_receiver.h"

#include <gtest/gtest.h>

#include <cmath>

#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::sim {
namespace {

Dataset rover() {
  SimulationOptions options;
  options.scenario = "rover";
  return simulate(options);
}

TEST(GpsReceiver, WithoutNoiseGivesTheAntennaInEnu) {
  const Dataset d = rover();
  GpsOptions o;
  o.horizontal_sigma = o.vertical_sigma = 0;
  o.world_origin_enu = {10, -20, 3};
  const GpsTrack gps = simulate_gps(d, o);
  ASSERT_EQ(gps.fixes.size(),
            static_cast<size_t>(std::floor((d.timestamps.back() - d.timestamps.front()) * o.rate_hz)) + 1);
  // At a frame's time the fix is that frame's antenna, turned by the heading about the vertical.
  const Eigen::Isometry3d world_from_body = d.world_from_cam.front() * gps.body_from_cam.inverse();
  const Eigen::Vector3d antenna_world = world_from_body * o.antenna_in_body;
  const double c = std::cos(o.world_heading), s = std::sin(o.world_heading);
  const Eigen::Vector3d expected(c * antenna_world.x() - s * antenna_world.y() + 10,
                                 s * antenna_world.x() + c * antenna_world.y() - 20,
                                 antenna_world.z() + 3);
  EXPECT_NEAR(gps.fixes.front().timestamp, d.timestamps.front(), 1e-12);
  EXPECT_LT((gps.fixes.front().enu - expected).norm(), 1e-12);
  EXPECT_NEAR(gps.latitude_deg, o.latitude_deg, 0);
}

TEST(GpsReceiver, NoiseHasTheStatedSpread) {
  const Dataset d = rover();
  GpsOptions exact;
  exact.horizontal_sigma = exact.vertical_sigma = 0;
  exact.rate_hz = 20;
  GpsOptions noisy = exact;
  noisy.horizontal_sigma = 0.5;
  noisy.vertical_sigma = 1.0;
  const GpsTrack a = simulate_gps(d, exact), b = simulate_gps(d, noisy);
  ASSERT_EQ(a.fixes.size(), b.fixes.size());
  ASSERT_GT(a.fixes.size(), 1000u);
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < a.fixes.size(); ++i)
    sum_sq += (b.fixes[i].enu - a.fixes[i].enu).cwiseAbs2();
  const Eigen::Vector3d sd = (sum_sq / a.fixes.size()).cwiseSqrt();
  // With n > 1000 samples the sample deviation is within 10 % of the truth (about 4 sigma).
  EXPECT_NEAR(sd.x(), 0.5, 0.05);
  EXPECT_NEAR(sd.y(), 0.5, 0.05);
  EXPECT_NEAR(sd.z(), 1.0, 0.1);
}

TEST(GpsReceiver, RefusesBadOptions) {
  const Dataset d = rover();
  GpsOptions o;
  o.rate_hz = 0;
  EXPECT_THROW(simulate_gps(d, o), std::invalid_argument);
  o = GpsOptions();
  o.vertical_sigma = -1;
  EXPECT_THROW(simulate_gps(d, o), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
