#include "omnisfm/sfm/track_consistency.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <vector>

#include "omnisfm/core/chi_square.h"
#include "omnisfm/core/percentile.h"

namespace omnisfm::sfm {
namespace {

constexpr int kMinTracksForNoise = 5;
// At least two tracks above the 90th percentile.
constexpr int kMinTracksForRampNoise = 20;

double track_degrees_of_freedom(const TrackResidualSum& s) { return 2.0 * s.sightings - 3; }

}  // namespace

void TrackResidualSum::add(int frame, const Eigen::Vector2d& residual_px) {
  insert(frame, residual_px);
}

void TrackResidualSum::add(int frame, const Eigen::Vector2d& residual_px,
                           const Eigen::Matrix<double, 2, 3>& point_jacobian) {
  point_jacobians.insert(point_jacobians.begin() + insert(frame, residual_px), point_jacobian);
}

std::ptrdiff_t TrackResidualSum::insert(int frame, const Eigen::Vector2d& residual_px) {
  ++sightings;
  const double norm = residual_px.norm();
  squared_px2 += norm * norm;
  if (worst_frame < 0 || norm > worst_px) {
    worst_frame = frame;
    worst_px = norm;
  }
  // In the frames' order, whatever the order given.
  const auto at = std::upper_bound(frames.begin(), frames.end(), frame) - frames.begin();
  frames.insert(frames.begin() + at, frame);
  residuals_px.insert(residuals_px.begin() + at, residual_px);
  return at;
}

std::vector<double> ramp_statistics(const TrackResidualSum& sum) {
  // The ramp from start k is A_k b with A_k = (f_j - f_k) I for j >= k. Its statistic is
  // m^T (A_k^T (I - P) A_k)^-1 m with m = A_k^T (I - P) r, P the projection onto the point's
  // Jacobians J (r is orthogonal to them only where the solution converged exactly):
  //   A_k^T A_k = sum (f_j - f_k)^2 I,  A_k^T J = sum (f_j - f_k) J_j,
  // all from suffix sums (frames counted from the first, so the squares stay small).
  const int n = static_cast<int>(sum.frames.size());
  const bool with_point = static_cast<int>(sum.point_jacobians.size()) == n;
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();
  Eigen::Vector3d along_point = Eigen::Vector3d::Zero();  // J^T r
  if (with_point)
    for (int j = 0; j < n; ++j) {
      information += sum.point_jacobians[j].transpose() * sum.point_jacobians[j];
      along_point += sum.point_jacobians[j].transpose() * sum.residuals_px[j];
    }
  // Its pseudo-inverse: a track with no parallax fixes its point's direction only, and leaves
  // the depth free (to a part in 10^9).
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> point_directions(information);
  Eigen::Matrix3d point_inverse = Eigen::Matrix3d::Zero();
  const double largest = point_directions.eigenvalues()[2];
  for (int i = 0; i < 3; ++i)
    if (point_directions.eigenvalues()[i] > 1e-9 * largest)
      point_inverse += point_directions.eigenvectors().col(i) *
                       point_directions.eigenvectors().col(i).transpose() /
                       point_directions.eigenvalues()[i];
  const bool point_fixed = with_point && largest > 0;
  Eigen::Vector2d r_sum = Eigen::Vector2d::Zero(), fr_sum = Eigen::Vector2d::Zero();
  Eigen::Matrix<double, 2, 3> j_sum = Eigen::Matrix<double, 2, 3>::Zero(), fj_sum = j_sum;
  double f_sum = 0, ff_sum = 0;
  std::vector<double> statistics(n, 0.0);
  for (int k = n - 1; k >= 0; --k) {
    const double f = sum.frames[k] - sum.frames[0];
    r_sum += sum.residuals_px[k];
    fr_sum += f * sum.residuals_px[k];
    f_sum += f;
    ff_sum += f * f;
    if (point_fixed) {
      j_sum += sum.point_jacobians[k];
      fj_sum += f * sum.point_jacobians[k];
    }
    if (n - k < 2) continue;
    const double spread = ff_sum - 2 * f * f_sum + f * f * (n - k);
    Eigen::Matrix2d ramp_information = spread * Eigen::Matrix2d::Identity();
    Eigen::Vector2d moment = fr_sum - f * r_sum;
    if (point_fixed) {
      const Eigen::Matrix<double, 2, 3> coupling = fj_sum - f * j_sum;
      ramp_information -= coupling * point_inverse * coupling.transpose();
      moment -= coupling * point_inverse * along_point;
    }
    // Only the ramp's directions a move of the point does not make as well (beyond a part in
    // 10^6 of its spread) tell anything.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> directions(ramp_information);
    const Eigen::Vector2d along = directions.eigenvectors().transpose() * moment;
    double statistic = 0;
    for (int i = 0; i < 2; ++i)
      if (directions.eigenvalues()[i] > 1e-6 * spread)
        statistic += along[i] * along[i] / directions.eigenvalues()[i];
    statistics[k] = statistic;
  }
  return statistics;
}

double largest_ramp_statistic(const TrackResidualSum& sum, double noise_px) {
  const std::vector<double> statistics = ramp_statistics(sum);
  return statistics.empty() ? 0.0
                            : *std::max_element(statistics.begin(), statistics.end()) /
                                  (noise_px * noise_px);
}

double measured_track_noise_px(const std::map<int, TrackResidualSum>& sums) {
  // Each track's variance per coordinate, over the median a chi-square of its degrees of freedom
  // takes (Wilson-Hilferty: dof (1 - 2 / (9 dof))^3), so that short tracks do not pull the noise
  // below what the long ones show.
  std::vector<double> variances;
  for (const auto& [track, s] : sums) {
    const double dof = track_degrees_of_freedom(s);
    if (dof < 3) continue;
    const double median_fraction = std::pow(1 - 2 / (9 * dof), 3);
    variances.push_back(s.squared_px2 / dof / median_fraction);
  }
  if (static_cast<int>(variances.size()) < kMinTracksForNoise) return NAN;
  // The lower median, index (n - 1) / 2: with an even count, the better of the two middle tracks.
  return std::sqrt(core::percentile(variances, 0.5 - 0.5 / variances.size()));
}

InconsistentTracks inconsistent_tracks(const std::map<int, TrackResidualSum>& sums,
                                       double false_alarm, double stated_noise_px) {
  InconsistentTracks result;
  result.measured_noise_px = measured_track_noise_px(sums);
  double variance = stated_noise_px * stated_noise_px;
  if (std::isfinite(result.measured_noise_px))
    variance = std::max(variance, result.measured_noise_px * result.measured_noise_px);
  // The ramp's noise from each track's whole-length ramp, a chi-square of 2 for a good track, at
  // the 90th percentile (2 ln 10): a camera a little off makes the residuals smooth where its
  // error is largest, which the ramp gathers more of than the sum. With fewer than 20 tracks the
  // percentile would be the worst track's own, and hide it. (Leaving out the tracks that fail the
  // sum leaves out those a camera far off bends most: 3 more good tracks rejected in 20
  // courtyards.) Each track's ramps are computed once: the whole-length one for the noise, the
  // largest for the test.
  std::map<int, std::pair<double, double>> ramps;  // track -> (whole length, largest)
  std::vector<double> ramp_variances;
  for (const auto& [track, s] : sums) {
    const std::vector<double> statistics = ramp_statistics(s);
    if (statistics.empty()) continue;
    ramps[track] = {statistics.front(), *std::max_element(statistics.begin(), statistics.end())};
    if (track_degrees_of_freedom(s) >= 3)
      ramp_variances.push_back(statistics.front() / (2 * std::log(10.0)));
  }
  double ramp_variance = variance;
  if (static_cast<int>(ramp_variances.size()) >= kMinTracksForRampNoise)
    ramp_variance = std::max(variance, core::percentile(ramp_variances, 0.9));
  if (!(variance > 0)) return result;
  result.noise_px = std::sqrt(variance);
  result.ramp_noise_px = std::sqrt(ramp_variance);
  for (const auto& [track, s] : sums) {
    const auto ramp = ramps.find(track);
    // The false alarm halved between the two statistics, as in exceeds_its_noise.
    if (sum_exceeds_its_noise(s, result.noise_px, false_alarm / 2) ||
        (ramp != ramps.end() && track_degrees_of_freedom(s) >= 1 &&
         ramp->second.second / ramp_variance > ramp_limit(s, false_alarm / 2)))
      result.tracks[track] = s.worst_frame;
  }
  return result;
}

bool exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double ramp_noise_px,
                       double false_alarm) {
  // The false alarm halved between the two statistics.
  return sum_exceeds_its_noise(sum, noise_px, false_alarm / 2) ||
         ramp_exceeds_its_noise(sum, ramp_noise_px, false_alarm / 2);
}

bool sum_exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double false_alarm) {
  const double dof = track_degrees_of_freedom(sum);
  return dof >= 1 && sum.squared_px2 / (noise_px * noise_px) >
                         core::chi_square_upper_quantile(dof, false_alarm);
}

bool ramp_exceeds_its_noise(const TrackResidualSum& sum, double noise_px, double false_alarm) {
  if (track_degrees_of_freedom(sum) < 1) return false;
  return largest_ramp_statistic(sum, noise_px) > ramp_limit(sum, false_alarm);
}

double ramp_limit(const TrackResidualSum& sum, double false_alarm) {
  // Shared among the starts (Bonferroni: the starts' statistics are correlated, so a good track
  // fails less often than this); chi-square with 2 degrees of freedom exceeds -2 ln p with
  // probability p.
  const int starts = std::max(1, sum.sightings - 1);
  return -2 * std::log(false_alarm / starts);
}

}  // namespace omnisfm::sfm
