#include "omnisfm/eval/trajectory_errors.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace omnisfm::eval {
namespace {

double angle_deg(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle() * 180 / M_PI;
}

double wrap(double a) { return std::remainder(a, 2 * M_PI); }

}  // namespace

TrajectoryErrors trajectory_errors(const std::vector<Eigen::Isometry3d>& estimate,
                                   const std::vector<Eigen::Isometry3d>& truth, bool with_scale) {
  if (estimate.size() != truth.size())
    throw std::invalid_argument("the estimate has " + std::to_string(estimate.size()) +
                                " poses, the ground truth " + std::to_string(truth.size()));
  const size_t n = truth.size();
  if (n < 3) throw std::invalid_argument("need at least 3 poses to align trajectories");
  std::vector<Eigen::Vector3d> a, b;
  for (size_t i = 0; i < n; ++i) {
    a.push_back(estimate[i].translation());
    b.push_back(truth[i].translation());
  }
  TrajectoryErrors e;
  e.alignment = align(a, b, with_scale);
  for (size_t i = 1; i < n; ++i) e.distance_travelled_m += (b[i] - b[i - 1]).norm();

  Eigen::Matrix3d rotation_sum = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Matrix3d> aligned_rotations;
  double sum = 0, sum2 = 0, rotation_sum_deg = 0, yaw_sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double d = (e.alignment.apply(a[i]) - b[i]).norm();
    e.translation_errors_m.push_back(d);
    sum += d;
    sum2 += d * d;
    const Eigen::Matrix3d R = e.alignment.rotation * estimate[i].linear();
    aligned_rotations.push_back(R);
    rotation_sum += R;
    rotation_sum_deg += angle_deg(truth[i].linear().transpose() * R);
    const Eigen::Matrix3d& T = truth[i].linear();
    yaw_sum += std::abs(wrap(std::atan2(R(1, 0), R(0, 0)) - std::atan2(T(1, 0), T(0, 0))));
  }
  e.mean_translation_error_m = sum / n;
  e.rms_translation_error_m = std::sqrt(sum2 / n);
  e.translation_error_percent =
      e.distance_travelled_m > 0 ? 100 * e.mean_translation_error_m / e.distance_travelled_m : 0;
  e.mean_rotation_error_deg = rotation_sum_deg / n;
  e.mean_yaw_error_deg = yaw_sum / n * 180 / M_PI;
  // The chordal mean rotation: the nearest rotation to the mean of the matrices.
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotation_sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d mean = svd.matrixU() * svd.matrixV().transpose();
  if (mean.determinant() < 0) {
    Eigen::Matrix3d flip = Eigen::Matrix3d::Identity();
    flip(2, 2) = -1;
    mean = svd.matrixU() * flip * svd.matrixV().transpose();
  }
  double spread = 0;
  for (const auto& R : aligned_rotations) spread += angle_deg(mean.transpose() * R);
  e.rotation_spread_deg = spread / n;
  return e;
}

PointErrors point_errors(const std::map<int, Eigen::Vector3d>& estimate,
                         const std::map<int, Eigen::Vector3d>& truth,
                         const std::vector<Eigen::Isometry3d>& estimate_poses,
                         const std::vector<Eigen::Isometry3d>& truth_poses,
                         const Similarity& alignment) {
  PointErrors e;
  if (truth_poses.empty() || estimate_poses.size() != truth_poses.size()) return e;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& T : truth_poses) centroid += T.translation();
  centroid /= truth_poses.size();
  double best = INFINITY;
  for (size_t i = 0; i < truth_poses.size(); ++i) {
    const double d = (truth_poses[i].translation() - centroid).norm();
    if (d < best) {
      best = d;
      e.centre_frame = static_cast<int>(i);
    }
  }
  const Eigen::Vector3d centre_truth = truth_poses[e.centre_frame].translation();
  const Eigen::Vector3d centre_estimate =
      alignment.apply(estimate_poses[e.centre_frame].translation());
  double sum = 0, sum_percent = 0;
  for (const auto& [track, X] : estimate) {
    const auto t = truth.find(track);
    if (t == truth.end()) continue;
    const double depth_truth = (t->second - centre_truth).norm();
    const double depth_estimate = (alignment.apply(X) - centre_estimate).norm();
    sum += std::abs(depth_estimate - depth_truth);
    sum_percent += 100 * std::abs(depth_estimate - depth_truth) / depth_truth;
    ++e.num_points;
  }
  if (e.num_points > 0) {
    e.mean_depth_error_m = sum / e.num_points;
    e.mean_depth_error_percent = sum_percent / e.num_points;
  }
  return e;
}

OutlierDetection outlier_detection(const std::set<int>& detected, const std::set<int>& actual) {
  OutlierDetection o;
  o.detected = static_cast<int>(detected.size());
  o.actual = static_cast<int>(actual.size());
  for (int t : detected) o.correct += actual.count(t);
  if (o.detected > 0) o.precision = static_cast<double>(o.correct) / o.detected;
  if (o.actual > 0) o.recall = static_cast<double>(o.correct) / o.actual;
  return o;
}

double travel_direction_error_deg(const std::vector<Eigen::Isometry3d>& estimate,
                                  const std::vector<Eigen::Isometry3d>& truth, int f, int span) {
  const auto travel = [f, span](const std::vector<Eigen::Isometry3d>& poses) {
    return Eigen::Vector3d(poses.at(f).linear().transpose() *
                           (poses.at(f + span).translation() - poses[f].translation()))
        .normalized();
  };
  return std::acos(std::clamp(travel(estimate).dot(travel(truth)), -1.0, 1.0)) * 180 / M_PI;
}

}  // namespace omnisfm::eval
