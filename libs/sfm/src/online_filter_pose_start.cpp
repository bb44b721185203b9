// The iterated update's first linearisation point in frames without new points: the posterior's
// minimum along the pose's direction of the prior.
//
// The prediction can be centimetres and degrees from where the frame was taken, and an update
// linearised there leaves errors of a tenth of a pixel, so a second full linearisation (P H^T, S
// and its factor: most of a frame's work after the covariance downdate) followed in nearly every
// frame. Here the state moves only as x(delta) = x_prior + P_{x,pose} P_pose^-1 delta: the pose
// by delta and every point by what the prior says it does when the pose does (its mean given
// the pose). One Gauss-Newton step on the posterior cost in delta uses the measurements' own
// Jacobians at the prior, so it costs one projection of the points; from there a single full
// update usually settles. It also serves while depths are still uncertain (on the rover, 1.61
// linearisations per frame where waiting for every depth to be known to 10 % took 1.84, at the
// same accuracy); a start that does not lower the posterior cost is not taken.

#include <Eigen/Cholesky>
#include <algorithm>

#include "omnisfm/sfm/online_filter.h"
#include "so3.h"

namespace omnisfm::sfm {
namespace {

// Fewer points than this leave the pose to the full update.
constexpr int kMinPoints = 3;
// Huber's threshold in multiples of the median residual (and at least the outlier threshold):
// a track that slid to a nearby feature must not drag the pose, and the outlier test deals with
// it after the update.
constexpr double kRobustMedians = 3;

}  // namespace

bool OnlineFilter::start_on_pose_subspace(const std::vector<Measurement>& meas,
                                          const std::vector<int>& point_columns,
                                          Iterate* prior) const {
  const int m = static_cast<int>(meas.size());
  const Eigen::MatrixXd& P = state_.P;
  const int n = static_cast<int>(P.rows());
  if (m < kMinPoints) return false;

  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> pose_prior(P.topLeftCorner<6, 6>());
  if (pose_prior.info() != Eigen::Success) return false;
  // Column j: how the state moves per unit of the pose's j-th coordinate.
  const Eigen::MatrixXd along = pose_prior.solve(P.topRows<6>()).transpose();  // n x 6
  const Eigen::Matrix<double, 6, 6> pose_information =
      pose_prior.solve(Eigen::Matrix<double, 6, 6>::Identity());
  const double variance = pixel_sigma() * pixel_sigma();

  std::vector<double> residual_norms(m);
  for (int k = 0; k < m; ++k) residual_norms[k] = prior->residual.segment<2>(2 * k).norm();
  std::nth_element(residual_norms.begin(), residual_norms.begin() + m / 2, residual_norms.end());
  const double huber =
      std::max(residual_limit_px(), kRobustMedians * residual_norms[m / 2]);

  // One Gauss-Newton step from delta = 0, where the prior's part of the gradient vanishes.
  Eigen::Matrix<double, 6, 6> A = pose_information;
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (int k = 0; k < m; ++k) {
    const Eigen::Matrix<double, 2, 6> J =
        prior->H_pose.middleRows<2>(2 * k) +
        prior->H_point[k] * along.middleRows<FilterState::kPointSize>(point_columns[k]);
    const Eigen::Vector2d r = prior->residual.segment<2>(2 * k);
    const double w = (r.norm() <= huber ? 1.0 : huber / r.norm()) / variance;
    A.noalias() += w * J.transpose() * J;
    b.noalias() += w * J.transpose() * r;
  }
  const Eigen::Matrix<double, 6, 1> delta = A.ldlt().solve(b);

  // The iterate x_0 = x_prior + P g, g being P_pose^-1 delta on the pose and zero elsewhere.
  Iterate start = *prior;
  start.offset = along * delta;
  start.offset.head<6>() = delta;
  state_.hold_considered(&start.offset);
  const FilterMean moved = state_.mean.plus(start.offset, kMinInverseDepth);
  start.offset.tail(n - state_.first_point_column()) = moved.points - state_.mean.points;
  start.g = Eigen::VectorXd::Zero(n);
  start.g.head<6>() = pose_information * delta;
  start.cost = start.g.head<6>().dot(delta);
  const Eigen::Matrix3d chart = so3::left_jacobian(delta.head<3>());
  for (int k = 0; k < m; ++k) {
    const int s = meas[k].slot;
    Linearisation lin;
    if (!linearise(state_.anchor(s), moved.R, moved.t, moved.params(s), true, &lin)) return false;
    start.cost += start.take(k, lin, meas[k].pixel, point_columns[k], chart, true) / variance;
  }
  // Only a start nearer the posterior's minimum than the prediction is worth taking.
  if (!(start.cost < prior->cost)) return false;
  std::swap(*prior, start);
  return true;
}

}  // namespace omnisfm::sfm
