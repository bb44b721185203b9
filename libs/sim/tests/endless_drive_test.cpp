// The endless drive: the same frames however far it is read, tracks of the stated length, and
// only the window near the current frame held.

#include "omnisfm/sim/endless_drive.h"

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>

#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/sim/trajectories.h"

namespace omnisfm::sim {
namespace {

TEST(EndlessDrive, AShorterDriveIsTheLongerOnesBeginning) {
  const Dataset short_drive = long_drive(400, 0.2, 3);
  const Dataset longer = long_drive(900, 0.2, 3);
  ASSERT_EQ(short_drive.world_from_cam.size(), 400u);
  for (size_t f = 0; f < 400; ++f)
    EXPECT_TRUE(short_drive.world_from_cam[f].isApprox(longer.world_from_cam[f], 0));
  ASSERT_LT(short_drive.observations.size(), longer.observations.size());
  // Up to the tracks the shorter drive's end cuts to a single observation.
  for (size_t k = 0; short_drive.observations[k].frame < 399; ++k) {
    EXPECT_EQ(short_drive.observations[k].track, longer.observations[k].track);
    EXPECT_EQ(short_drive.observations[k].pixel, longer.observations[k].pixel);
  }
  for (size_t t = 0; t < short_drive.track_points.size(); ++t)
    EXPECT_EQ(short_drive.track_points[t], longer.track_points[t]);
  const Dataset other_seed = long_drive(400, 0.2, 4);
  EXPECT_NE(other_seed.track_points[0], short_drive.track_points[0]);
}

TEST(EndlessDrive, FramesSeeAboutThirtyTracksOfTheirNeighbourhood) {
  const Dataset d = long_drive(2000, 0.0, 1);
  std::map<int, int> per_frame, length;
  for (const auto& o : d.observations) {
    ++per_frame[o.frame];
    ++length[o.track];
    // A track is seen from the frames within 15 of its own.
    EXPECT_GE(o.frame, o.track - 15);
    EXPECT_LT(o.frame, o.track + 15);
    // Without noise, the pixel is the true point's.
    Eigen::Vector2d pixel;
    ASSERT_TRUE(true_pixel(d, o.frame, d.track_points[o.track], &pixel));
    EXPECT_LT((pixel - o.pixel).norm(), 1e-9);
  }
  ASSERT_EQ(per_frame.size(), 2000u);
  for (const auto& [track, n] : length) EXPECT_GE(n, 2) << "track " << track;
  for (const auto& [frame, count] : per_frame) {
    EXPECT_GE(count, frame < 15 ? 12 : 24) << "frame " << frame;
    EXPECT_LE(count, 30) << "frame " << frame;
  }
  int long_tracks = 0;
  for (const auto& [track, n] : length) long_tracks += n >= 24;
  // All but the tracks cut by the drive's first and last frames.
  EXPECT_GE(long_tracks, 2000 - 30);
  // 3 cm per frame along a gentle S, half a second apart.
  EXPECT_NEAR(d.timestamps[1999], 999.5, 1e-9);
  EXPECT_NEAR(path_length(d.world_from_cam), 1999 * EndlessDrive::kStep, 1e-9);
}

TEST(EndlessDrive, HoldsOnlyTheTracksNearTheCurrentFrame) {
  EndlessDrive drive(default_rig(1024, 768), 0.2, 1);
  for (int f = 0; f < 100; ++f) drive.next();
  // Frame 99 sees tracks 85 .. 114.
  EXPECT_NO_THROW(drive.true_point(85));
  EXPECT_NO_THROW(drive.true_point(114));
  EXPECT_THROW(drive.true_point(84), std::out_of_range);
  EXPECT_THROW(drive.true_point(115), std::out_of_range);
}

TEST(EndlessDrive, IsAScenario) {
  SimulationOptions options;
  options.scenario = "drive";
  options.frames = 300;
  options.seed = 5;
  const Dataset d = simulate(options);
  EXPECT_EQ(d.scenario, "drive");
  EXPECT_EQ(d.world_from_cam.size(), 300u);
  EXPECT_EQ(d.timestamps.size(), 300u);
  EXPECT_TRUE(d.outliers.empty());
  EXPECT_EQ(d.observations.size(), long_drive(300, 0.2, 5).observations.size());
  options.frames = 1;
  EXPECT_THROW(simulate(options), std::invalid_argument);
  EXPECT_THROW(EndlessDrive(default_rig(1024, 768), -1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
