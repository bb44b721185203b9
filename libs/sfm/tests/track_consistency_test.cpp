#include "omnisfm/sfm/track_consistency.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>

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
    sum.add(f, {noise(*rng) + drift, noise(*rng)});
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

// The chance the sum's test gives is the chance a good track fails it, at the stated noise. Each
// track's residuals are Gaussian in exactly 2n - 3 coordinates (3 taken by its point).
TEST(TrackConsistency, GoodTracksFailTheSumAtTheStatedRate) {
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.3);
  std::uniform_int_distribution<int> length(3, 120);
  int failed = 0;
  for (int trial = 0; trial < 10000; ++trial) {
    const int sightings = length(rng);
    TrackResidualSum sum;
    for (int f = 0; f + 2 < sightings; ++f) sum.add(f, {noise(rng), noise(rng)});
    sum.add(sightings - 2, {noise(rng), 0});
    sum.add(sightings - 1, {0, 0});
    failed += sum_exceeds_its_noise(sum, 0.3, 0.01);
  }
  // 99.7 expected of 10,000 with the approximate quantile; the binomial's sigma is 10. With 2n
  // degrees of freedom assumed it would be 55, with 2n - 2 81, with 2n - 4 124.
  std::printf("good tracks failed the sum: %d of 10,000\n", failed);
  EXPECT_GT(failed, 72);
  EXPECT_LT(failed, 120);
}

// White residuals beside a move of the point: `n` sightings whose Jacobians make a ramp as the
// point moves (its depth: a drift along the parallax), the noise less what the point takes.
TrackResidualSum white_beside_the_point(std::mt19937* rng, int n, double sigma) {
  std::normal_distribution<double> noise(0, sigma);
  Eigen::MatrixXd J(2 * n, 3);
  Eigen::VectorXd e(2 * n);
  for (int f = 0; f < n; ++f) {
    J.block<2, 3>(2 * f, 0) << 1, 0, 0.05 * f + 0.002 * f * f, 0, 1, 0.02 * f;
    e.segment<2>(2 * f) << noise(*rng), noise(*rng);
  }
  const Eigen::VectorXd r = e - J * (J.transpose() * J).ldlt().solve(J.transpose() * e);
  TrackResidualSum sum;
  for (int f = 0; f < n; ++f)
    sum.add(f, r.segment<2>(2 * f), J.block<2, 3>(2 * f, 0));
  return sum;
}

// From any start the ramp's statistic of a good track is a chi-square of 2 (mean 2), once what a
// move of the point makes of the ramp is taken out of its variance; left in, the mean from the
// first sighting is 0.27 for this track's Jacobians.
TEST(TrackConsistency, TheRampBesideAMoveOfThePointIsAChiSquareOfTwo) {
  std::mt19937 rng(5);
  double from_first = 0, from_middle = 0, without_point = 0;
  const int trials = 4000;
  for (int trial = 0; trial < trials; ++trial) {
    TrackResidualSum sum = white_beside_the_point(&rng, 40, 0.5);
    const std::vector<double> statistics = ramp_statistics(sum);
    from_first += statistics[0] / 0.25;
    from_middle += statistics[20] / 0.25;
    sum.point_jacobians.clear();
    without_point += ramp_statistics(sum)[0] / 0.25;
  }
  // The mean of 4,000 chi-squares of 2 is within 0.13 (4 of its sigmas) of 2.
  EXPECT_NEAR(from_first / trials, 2, 0.13);
  EXPECT_NEAR(from_middle / trials, 2, 0.13);
  EXPECT_NEAR(without_point / trials, 0.27, 0.05);
}

// A track with no parallax fixes its point's direction only (its Jacobians leave the depth
// free): the ramp is judged beside a move of the direction, not beside nothing.
TEST(TrackConsistency, ATrackWithoutParallaxIsJudgedBesideItsDirection) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.5);
  double from_first = 0;
  const int trials = 4000, n = 30;
  for (int trial = 0; trial < trials; ++trial) {
    // Its direction takes each coordinate's mean.
    Eigen::MatrixXd e(n, 2);
    for (int f = 0; f < n; ++f) e.row(f) << noise(rng), noise(rng);
    const Eigen::RowVector2d mean = e.colwise().mean();
    TrackResidualSum sum;
    for (int f = 0; f < n; ++f)
      sum.add(f, (e.row(f) - mean).transpose(), Eigen::Matrix<double, 2, 3>::Identity());
    from_first += ramp_statistics(sum)[0] / 0.25;
  }
  EXPECT_NEAR(from_first / trials, 2, 0.13);
}

// The statistic from each start against its definition, m^T (A^T (I - P) A)^+ m with
// m = A^T (I - P) r (A the ramp's columns, P the projection onto the point's Jacobians), for
// residuals the point does not fit exactly (a solve stopped early), frames with gaps and far from
// 0, added out of order.
TEST(TrackConsistency, TheRampsStatisticIsItsDefinition) {
  std::mt19937 rng(8);
  std::normal_distribution<double> normal(0, 1);
  std::uniform_int_distribution<int> gap(1, 4);
  for (const int n : {3, 7, 25}) {
    std::vector<int> frames;
    for (int f = 1000; static_cast<int>(frames.size()) < n; f += gap(rng)) frames.push_back(f);
    Eigen::MatrixXd J(2 * n, 3);
    Eigen::VectorXd r(2 * n);
    for (int j = 0; j < 2 * n; ++j) {
      for (int c = 0; c < 3; ++c) J(j, c) = normal(rng);
      r[j] = normal(rng);
    }
    TrackResidualSum sum;
    for (int j = n - 1; j >= 0; --j)
      sum.add(frames[j], r.segment<2>(2 * j), J.block<2, 3>(2 * j, 0));
    const std::vector<double> statistics = ramp_statistics(sum);
    ASSERT_EQ(statistics.size(), static_cast<size_t>(n));
    const Eigen::MatrixXd P = J * (J.transpose() * J).inverse() * J.transpose();
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(2 * n, 2 * n);
    for (int k = 0; k + 1 < n; ++k) {
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2);
      for (int j = k; j < n; ++j)
        A.block<2, 2>(2 * j, 0) = (frames[j] - frames[k]) * Eigen::Matrix2d::Identity();
      const Eigen::Vector2d m = A.transpose() * (I - P) * r;
      const Eigen::Matrix2d information = A.transpose() * (I - P) * A;
      const double expected = m.dot(information.completeOrthogonalDecomposition().solve(m));
      EXPECT_NEAR(statistics[k], expected, 1e-9 * std::max(1.0, expected)) << n << " " << k;
    }
  }
}

// Good tracks fail the ramp's test at most at the stated rate (its starts' statistics are
// correlated, so less often).
TEST(TrackConsistency, GoodTracksFailTheRampAtMostAtTheStatedRate) {
  std::mt19937 rng(12);
  std::uniform_int_distribution<int> length(4, 120);
  int failed = 0;
  for (int trial = 0; trial < 10000; ++trial)
    failed += ramp_exceeds_its_noise(white_beside_the_point(&rng, length(rng), 0.3), 0.3, 0.01);
  // 17 measured; a threshold too high would give none, one at chi-square(2)'s own 1 % hundreds.
  std::printf("good tracks failed the ramp: %d of 10,000\n", failed);
  EXPECT_GE(failed, 5);
  EXPECT_LT(failed, 100);
}

// Both together, as the batch judges its tracks: at most the stated rate, and more than the sum
// alone at its half.
TEST(TrackConsistency, GoodTracksFailTheWholeTrackTestAtMostAtTheStatedRate) {
  std::mt19937 rng(13);
  std::uniform_int_distribution<int> length(4, 120);
  int failed = 0, failed_the_sum = 0;
  for (int trial = 0; trial < 10000; ++trial) {
    const TrackResidualSum sum = white_beside_the_point(&rng, length(rng), 0.3);
    failed += exceeds_its_noise(sum, 0.3, 0.3, 0.01);
    failed_the_sum += sum_exceeds_its_noise(sum, 0.3, 0.005);
  }
  std::printf("good tracks failed: %d of 10,000 (the sum at half the rate: %d)\n", failed,
              failed_the_sum);
  EXPECT_GT(failed, failed_the_sum);
  EXPECT_LT(failed, 100);
}

// A drift from halfway, too slow for the sum over the track's length, is a ramp far beyond the
// noise.
TEST(TrackConsistency, ADriftTooSlowForTheSumIsCaughtAsARamp) {
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, 0.2);
  std::map<int, TrackResidualSum> sums;
  for (int t = 0; t < 40; ++t) sums[t] = noisy_track(&rng, 100, 0.2);
  TrackResidualSum& drifting = sums[40];
  for (int f = 0; f < 100; ++f) {
    const double drift = 0.0077 * std::max(0, f - 50);  // 0.38 px by its end
    drifting.add(f, {noise(rng) + drift, noise(rng)});
  }
  EXPECT_FALSE(sum_exceeds_its_noise(drifting, 0.2, 1e-4 / 2));
  EXPECT_TRUE(ramp_exceeds_its_noise(drifting, 0.2, 1e-4 / 2));
  const InconsistentTracks found = inconsistent_tracks(sums, 1e-4, 0.2);
  ASSERT_EQ(found.tracks.size(), 1u);
  EXPECT_EQ(found.tracks.begin()->first, 40);
}

// A camera a little off makes every track's residuals smooth. Each ramp is beyond the stated
// noise, but the tracks' own ramps raise the ramp's noise, and only a drift beyond them fails.
TEST(TrackConsistency, ASmoothErrorTheTracksShareRaisesTheRampsNoise) {
  std::mt19937 rng(6);
  std::normal_distribution<double> noise(0, 0.2);
  std::uniform_real_distribution<double> size(0.8, 1.5);
  const auto ramped = [&](double end_px) {
    TrackResidualSum sum;
    for (int f = 0; f < 60; ++f)
      sum.add(f, {noise(rng) + end_px * (f / 59.0 - 0.5), noise(rng)});
    return sum;
  };
  std::map<int, TrackResidualSum> sums;
  int beyond_the_stated_noise = 0;
  for (int t = 0; t < 40; ++t) {
    sums[t] = ramped(size(rng));
    beyond_the_stated_noise += ramp_exceeds_its_noise(sums[t], 0.2, 1e-4 / 2);
  }
  sums[40] = ramped(4.0);
  EXPECT_GT(beyond_the_stated_noise, 10);
  const InconsistentTracks found = inconsistent_tracks(sums, 1e-4, 0.2);
  EXPECT_GT(found.ramp_noise_px, 1.5 * found.noise_px);
  ASSERT_EQ(found.tracks.size(), 1u);
  EXPECT_EQ(found.tracks.begin()->first, 40);
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
