#include "omnisfm/sfm/track_consistency.h"

#include <gtest/gtest.h>

#include <cstdio>
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

// The chance the test gives is the chance a good track fails, at the stated noise. Each track's
// residuals are Gaussian in exactly 2n - 3 coordinates (3 taken by its point), and four tracks
// at a time are too few to measure the noise, so the stated one judges them.
TEST(TrackConsistency, GoodTracksFailAtTheStatedRate) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.3);
  std::uniform_int_distribution<int> length(3, 120);
  int failed = 0;
  for (int trial = 0; trial < 2500; ++trial) {
    std::map<int, TrackResidualSum> sums;
    for (int t = 0; t < 4; ++t) {
      const int sightings = length(rng);
      TrackResidualSum& sum = sums[t];
      for (int f = 0; f + 2 < sightings; ++f) sum.add(f, std::hypot(noise(rng), noise(rng)));
      sum.add(sightings - 2, std::abs(noise(rng)));
      sum.add(sightings - 1, 0);
    }
    const InconsistentTracks found = inconsistent_tracks(sums, 0.01, 0.3);
    ASSERT_TRUE(std::isnan(found.measured_noise_px));
    failed += static_cast<int>(found.tracks.size());
  }
  // 99.7 expected of 10,000 with the approximate quantile; the binomial's sigma is 10. With 2n
  // degrees of freedom assumed it would be 55, with 2n - 2 81, with 2n - 4 124.
  std::printf("good tracks failed: %d of 10,000\n", failed);
  EXPECT_GT(failed, 72);
  EXPECT_LT(failed, 120);
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
