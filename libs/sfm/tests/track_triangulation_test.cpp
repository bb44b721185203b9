// One track's point from known poses: exact sightings give the point back, a sighting that slid
// to another feature leaves a residual of its slide, and sightings with no parallax give nothing.

#include "omnisfm/sfm/track_triangulation.h"

#include <gtest/gtest.h>

#include <random>

#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {
namespace {

struct Drive {
  camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  std::vector<Eigen::Isometry3d> cam_from_world;
  Eigen::Vector3d point{2.0, 1.0, -0.4};

  Drive() {
    for (int i = 0; i < 12; ++i) {
      Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
      world_from_cam.linear() = Eigen::AngleAxisd(0.03 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      world_from_cam.translation() << 0.05 * i, 0.01 * i, 0.6;
      cam_from_world.push_back(world_from_cam.inverse());
    }
  }
  std::vector<TrackSighting> sightings(double noise_px, std::uint64_t seed) const {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0, noise_px);
    std::vector<TrackSighting> out;
    for (const auto& T : cam_from_world) {
      Eigen::Vector2d pixel;
      EXPECT_TRUE(camera.project(T * point, &pixel));
      out.push_back({T, pixel + Eigen::Vector2d(noise(rng), noise(rng))});
    }
    return out;
  }
};

TEST(TrackTriangulation, ExactSightingsGiveThePointBack) {
  const Drive s;
  const TriangulatedTrack t = triangulate_track(s.camera, s.sightings(0, 1));
  ASSERT_TRUE(t.valid);
  EXPECT_LT((t.point - s.point).norm(), 1e-6);
  EXPECT_LT(t.largest_residual_px, 1e-6);
}

TEST(TrackTriangulation, NoisySightingsFitWithinTheirNoise) {
  const Drive s;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const TriangulatedTrack t = triangulate_track(s.camera, s.sightings(0.3, seed));
    ASSERT_TRUE(t.valid);
    // 24 coordinates less 3 parameters: the RMS is near 0.3 * sqrt(21 / 24) = 0.28.
    EXPECT_NEAR(t.rms_px, 0.28, 0.12) << seed;
    EXPECT_LT(t.largest_residual_px, 5 * 0.3 * std::sqrt(2.0)) << seed;
    EXPECT_LT((t.point - s.point).norm(), 0.1) << seed;
  }
}

TEST(TrackTriangulation, ASlideShowsInTheResiduals) {
  const Drive s;
  std::vector<TrackSighting> seen = s.sightings(0, 1);
  // The last third slides 4 px across the image: no point explains it.
  for (size_t i = 8; i < seen.size(); ++i) seen[i].pixel += Eigen::Vector2d(4, 0);
  const TriangulatedTrack t = triangulate_track(s.camera, seen);
  ASSERT_TRUE(t.valid);
  EXPECT_GT(t.largest_residual_px, 1.5);
}

TEST(TrackTriangulation, NoParallaxOrTooFewSightingsGiveNothing) {
  const Drive s;
  std::vector<TrackSighting> seen = s.sightings(0, 1);
  EXPECT_FALSE(triangulate_track(s.camera, {seen[0]}).valid);
  EXPECT_FALSE(triangulate_track(s.camera, {seen[0], seen[0], seen[0]}).valid);
}

}  // namespace
}  // namespace omnisfm::sfm
