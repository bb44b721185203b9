#include "omnisfm/sfm/track_consistency.h"

#include <gtest/gtest.h>

#include <random>

namespace omnisfm::sfm {
namespace {

// A track of `sightings` pixels with Gaussian noise `sigma` per coordinate, whose pixel moves
// away from its point by `drift_px` in all by its end.
TrackResidualSum noisy_track(std::mt19937* rng, int sightings, double sigma,
                             double drift_px = 0) {
  std::normal_distribution<double> noise(0, sigma);
  TrackResidualSum sum;
  for (int f = 0; f < sightings; ++f) {
    // A linear drift less its best-fitting constant, as the track's point takes that.
    const double drift = drift_px * (f / (sightings - 1.0) - 0.5);
    sum.add(f, std::hypot(noise(*rng) + drift, noise(*rng)));
  }
  return sum;
}

TEST(TrackConsistency, ASlowDriftIsRejectedAtTheStatedNoiseOrTheTracksOwnWhereLarger) {
  // Noise as stated, and five times what was stated.
  for (const double sigma : {0.2, 1.0}) {
    std::mt19937 rng(1);
    std::map<int, TrackResidualSum> sums;
    for (int t = 0; t < 40; ++t) sums[t] = noisy_track(&rng, 60, sigma);
    // Each residual within 2.5 sigmas of the noise, but over 60 sightings far beyond it.
    sums[40] = noisy_track(&rng, 60, sigma, 5 * sigma);
    const InconsistentTracks found = inconsistent_tracks(sums, 1e-4, 0.2);
    EXPECT_NEAR(found.measured_noise_px, sigma, 0.1 * sigma);
    EXPECT_NEAR(found.noise_px, sigma, 0.1 * sigma);
    ASSERT_EQ(found.tracks.size(), 1u) << sigma;
    EXPECT_EQ(found.tracks.begin()->first, 40);
    // Its frame is where it is worst: an end.
    const int frame = found.tracks.begin()->second;
    EXPECT_TRUE(frame < 10 || frame > 50) << frame;
  }
}

// A tracker's tracks differ in noise with their contrast: measured against the best half, the
// rest would look like drifts. Below the stated noise they are judged at it.
TEST(TrackConsistency, TracksQuieterThanStatedAreJudgedAtTheStatedNoise) {
  std::mt19937 rng(2);
  std::map<int, TrackResidualSum> sums;
  for (int t = 0; t < 100; ++t) sums[t] = noisy_track(&rng, 80, 0.02 + 0.001 * t);
  const InconsistentTracks found = inconsistent_tracks(sums, 1e-4, 0.3);
  EXPECT_LT(found.measured_noise_px, 0.1);
  EXPECT_EQ(found.noise_px, 0.3);
  EXPECT_TRUE(found.tracks.empty());
  // Judged at their own median noise instead, a third of them would be rejected.
  EXPECT_GT(inconsistent_tracks(sums, 1e-4, 0.01).tracks.size(), 25u);
}

// The chance the test gives is the chance a good track fails, at the stated noise.
TEST(TrackConsistency, GoodTracksFailAtTheStatedRate) {
  std::mt19937 rng(7);
  int failed = 0;
  for (int trial = 0; trial < 50; ++trial) {
    std::map<int, TrackResidualSum> sums;
    std::uniform_int_distribution<int> length(3, 120);
    for (int t = 0; t < 200; ++t) sums[t] = noisy_track(&rng, length(rng), 0.3);
    failed += static_cast<int>(inconsistent_tracks(sums, 0.01, 0.3).tracks.size());
  }
  // 100 expected of 10,000 (fewer where the measured median comes out above 0.3); the binomial's
  // sigma is 10.
  EXPECT_GT(failed, 60);
  EXPECT_LT(failed, 130);
}

TEST(TrackConsistency, TooFewTracksToMeasureTheNoiseAreJudgedAtTheStatedNoise) {
  std::mt19937 rng(3);
  std::map<int, TrackResidualSum> sums;
  for (int t = 0; t < 3; ++t) sums[t] = noisy_track(&rng, 50, 0.2);
  sums[3] = noisy_track(&rng, 2, 0.2);  // too short to weigh
  sums[4] = noisy_track(&rng, 50, 0.2, 10);
  const InconsistentTracks found = inconsistent_tracks(sums, 1e-4, 0.2);
  EXPECT_TRUE(std::isnan(found.measured_noise_px));
  EXPECT_EQ(found.noise_px, 0.2);
  ASSERT_EQ(found.tracks.size(), 1u);
  EXPECT_EQ(found.tracks.begin()->first, 4);
}

}  // namespace
}  // namespace omnisfm::sfm
