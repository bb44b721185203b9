// The filter's state: slots, mean and covariance kept in step by add and remove; the mean moved
// by plus; a point's parameters about its anchor and their Jacobian.

#include "omnisfm/sfm/filter_state.h"

#include "../src/so3.h"

#include <gtest/gtest.h>

#include <random>

namespace omnisfm::sfm {
namespace {

PointAnchor anchor_along(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  PointAnchor a;
  a.origin = origin;
  a.basis.col(0) = direction.normalized();
  a.basis.col(1) = a.basis.col(0).unitOrthogonal();
  a.basis.col(2) = a.basis.col(0).cross(a.basis.col(1));
  return a;
}

PointParams params_of(double a, double b, double rho, const Eigen::Vector3d& offset) {
  PointParams params;
  params << a, b, rho, offset;
  return params;
}

// A random positive-definite covariance over the state, the origin's error nothing yet (a
// considered block the reset keeps, as for an origin never moved).
void randomise_covariance(FilterState* state, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  const int n = static_cast<int>(state->P.rows());
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return 0.1 * normal(rng); });
  state->P = A * A.transpose() + 0.01 * Eigen::MatrixXd::Identity(n, n);
  state->P.middleRows<6>(FilterState::kOriginColumn).setZero();
  state->P.middleCols<6>(FilterState::kOriginColumn).setZero();
}

TEST(FilterState, WorldPointJacobianMatchesCentralDifferences) {
  const PointAnchor a = anchor_along({0.1, -0.2, 0.3}, {1, 2, -0.5});
  const PointParams params = params_of(0.02, -0.03, 0.4, {0.01, -0.02, 0.005});
  PointJacobian J;
  a.world_point(params, &J);
  const double h = 1e-6;
  for (int k = 0; k < FilterState::kPointSize; ++k) {
    PointParams up = params, down = params;
    up[k] += h;
    down[k] -= h;
    const Eigen::Vector3d numeric = (a.world_point(up) - a.world_point(down)) / (2 * h);
    EXPECT_LT((J.col(k) - numeric).norm(), 1e-6 * (1 + numeric.norm())) << "column " << k;
  }
  // params_of places the origin where the anchor says.
  const PointParams placed = params_of(0.02, -0.03, 0.4, Eigen::Vector3d::Zero());
  EXPECT_LT((a.params_of(a.world_point(placed)) - placed).norm(), 1e-12);
  EXPECT_LT((a.world_point(a.params_of(a.world_point(params))) - a.world_point(params)).norm(),
            1e-12);
}

// Three points added, the middle one removed: the last takes its slot, and the mean and every
// covariance entry follow it.
TEST(FilterState, RemoveMovesTheLastSlotWithItsCovariance) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> normal(0, 1);
  FilterState state;
  constexpr int kFixed = FilterState::kCameraColumn;  // the columns before the points
  const Eigen::MatrixXd A =
      Eigen::MatrixXd::NullaryExpr(kFixed, kFixed, [&] { return normal(rng); });
  state.P = A * A.transpose() + Eigen::MatrixXd::Identity(kFixed, kFixed);
  constexpr int kSize = FilterState::kPointSize;
  for (int track : {7, 8, 9}) {
    const Eigen::Matrix<double, kSize, 6> G =
        Eigen::Matrix<double, kSize, 6>::NullaryExpr([&] { return normal(rng); });
    const int slot = state.add(
        track, anchor_along(Eigen::Vector3d::Zero(), {1, static_cast<double>(track), 0}),
        params_of(0, 0, 0.1 * track, Eigen::Vector3d::Zero()), G,
        params_of(1, 2, 3, {4, 5, 6}));
    EXPECT_EQ(state.track_of(slot), track);
    // The point's error is G times the pose's plus its own.
    const int c = state.point_column(slot);
    EXPECT_LT((state.P.block<kSize, 6>(c, 0) - G * state.P.topLeftCorner<6, 6>()).norm(), 1e-12);
    EXPECT_NEAR(state.P(c + 2, c + 2),
                (G * state.P.topLeftCorner<6, 6>() * G.transpose())(2, 2) + 9, 1e-12);
  }
  ASSERT_EQ(state.P.rows(), state.point_column(3));
  const Eigen::MatrixXd before = state.P;
  state.remove(state.slot_of(8));
  EXPECT_EQ(state.num_slots(), 2);
  EXPECT_EQ(state.slot_of(8), -1);
  EXPECT_EQ(state.slot_of(7), 0);
  EXPECT_EQ(state.slot_of(9), 1);
  EXPECT_EQ(state.mean.points.size(), 2 * kSize);
  EXPECT_DOUBLE_EQ(state.mean.params(1)[2], 0.9);
  // Old columns of what is left: the pose, sensors and origin, track 7's, track 9's.
  std::vector<int> kept;
  for (int k = 0; k < kFixed; ++k) kept.push_back(k);
  for (int k = 0; k < kSize; ++k) kept.push_back(state.point_column(0) + k);
  for (int k = 0; k < kSize; ++k) kept.push_back(state.point_column(2) + k);
  ASSERT_EQ(state.P.rows(), static_cast<int>(kept.size()));
  for (size_t i = 0; i < kept.size(); ++i)
    for (size_t j = 0; j < kept.size(); ++j)
      EXPECT_EQ(state.P(i, j), before(kept[i], kept[j])) << i << ", " << j;
}

// What the world sees of a state under an error `delta` in the covariance's columns (the state
// frame's at kOriginColumn): the world pose's error (the rotation's a left perturbation, then the
// translation's) and each point's world position less the estimate's.
Eigen::VectorXd world_view(const FilterState& state, const Eigen::VectorXd& delta) {
  constexpr int kOrigin = FilterState::kOriginColumn;
  const FilterMean m = state.mean.plus(delta, 1e-3);
  Eigen::Isometry3d world_from_state = state.world_from_state();
  world_from_state.linear() = so3::exp(delta.segment<3>(kOrigin)) * world_from_state.linear();
  world_from_state.translation() += delta.segment<3>(kOrigin + 3);
  const Eigen::Isometry3d cam_from_world = m.cam_from_world() * world_from_state.inverse();
  const Eigen::Isometry3d estimate = state.world_cam_from_world();
  Eigen::VectorXd view(6 + 3 * state.num_slots());
  view.head<3>() = so3::log(cam_from_world.linear() * estimate.linear().transpose());
  view.segment<3>(3) = cam_from_world.translation() - estimate.translation();
  for (int s = 0; s < state.num_slots(); ++s)
    view.segment<3>(6 + 3 * s) = world_from_state * state.anchor(s).world_point(m.params(s)) -
                                 state.in_world(state.world_point(s));
  return view;
}

// world_view's Jacobian at no error, by central differences.
Eigen::MatrixXd world_view_jacobian(const FilterState& state) {
  const int n = static_cast<int>(state.P.rows());
  Eigen::MatrixXd J(6 + 3 * state.num_slots(), n);
  const double h = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd up = Eigen::VectorXd::Zero(n), down = up;
    up[k] = h;
    down[k] = -h;
    J.col(k) = (world_view(state, up) - world_view(state, down)) / (2 * h);
  }
  return J;
}

// A state whose frame has already moved once, its camera then elsewhere and turned, three points
// with angles off their first rays, and a random covariance.
FilterState moved_state(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0, 1);
  FilterState state;
  state.mean.R = Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 0.3, 1).normalized()).toRotationMatrix();
  state.mean.t << -4, 2, 0.5;
  state.move_origin_to_camera();
  state.mean.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  state.mean.t << 3, -1, 2;
  for (int track : {1, 2, 3})
    state.add(track, anchor_along({0.2 * track, -0.1, 0.3}, {1, 0.5 * track, -0.2}),
              params_of(0.05 * track, -0.08, 0.3 + 0.1 * track, {0.01, 0.02, -0.03}),
              Eigen::Matrix<double, FilterState::kPointSize, 6>::Zero(), PointParams::Ones());
  const int n = static_cast<int>(state.P.rows());
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(rng); });
  state.P = A * A.transpose() + Eigen::MatrixXd::Identity(n, n);
  return state;
}

// The moved state's error for an error `delta` of the state before the move, exactly: the state
// perturbed by delta, its frame moved to its own camera (or that camera's position), and
// expressed in the moved estimate's terms. A point's new parameters are its perturbed ray, turned
// and moved with the frame, about its moved anchor.
Eigen::VectorXd moved_error(const FilterState& before, const FilterState& after,
                            const Eigen::VectorXd& delta, bool position_only) {
  constexpr int kOrigin = FilterState::kOriginColumn;
  const FilterMean m = before.mean.plus(delta, 1e-6);
  Eigen::Isometry3d world_from_state = before.world_from_state();
  world_from_state.linear() = so3::exp(delta.segment<3>(kOrigin)) * world_from_state.linear();
  world_from_state.translation() += delta.segment<3>(kOrigin + 3);
  Eigen::Isometry3d new_from_old = m.cam_from_world();
  if (position_only) {
    new_from_old.linear().setIdentity();
    new_from_old.translation() = m.R.transpose() * m.t;
  }
  const Eigen::Isometry3d world_from_new = world_from_state * new_from_old.inverse();
  const Eigen::Isometry3d pose = m.cam_from_world() * new_from_old.inverse();
  Eigen::VectorXd e = delta;  // the sensors' and the camera's errors as they were
  e.head<3>() = so3::log(pose.linear() * after.mean.R.transpose());
  e.segment<3>(3) = pose.translation() - after.mean.t;
  e.segment<3>(kOrigin) =
      so3::log(world_from_new.linear() * after.world_from_state().linear().transpose());
  e.segment<3>(kOrigin + 3) = world_from_new.translation() - after.world_from_state().translation();
  for (int s = 0; s < before.num_slots(); ++s) {
    const PointAnchor& old_anchor = before.anchor(s);
    const PointAnchor& new_anchor = after.anchor(s);
    const PointParams p = m.params(s);
    const Eigen::Vector3d u = old_anchor.basis.col(0) + p[0] * old_anchor.basis.col(1) +
                              p[1] * old_anchor.basis.col(2);
    const Eigen::Vector3d d = new_from_old.linear() * u;
    const Eigen::Vector3d ray_origin = new_from_old * (old_anchor.origin + p.tail<3>());
    const double along = new_anchor.basis.col(0).dot(d);
    PointParams q;
    q << new_anchor.basis.col(1).dot(d) / along, new_anchor.basis.col(2).dot(d) / along, p[2],
        ray_origin - new_anchor.origin;
    e.segment<FilterState::kPointSize>(before.point_column(s)) = q - after.mean.params(s);
  }
  return e;
}

// Moving the state's frame to the camera, with its orientation or its position only, is a change
// of variables: every world quantity stays where it was, and the covariance is J P J^T with J the
// exact change's Jacobian by central differences (moved_error). The pose is then known exactly
// where the frame took it.
TEST(FilterState, MovingTheOriginToTheCameraKeepsTheWorldAndCarriesTheErrors) {
  for (bool position_only : {false, true}) {
    SCOPED_TRACE(position_only ? "position only" : "position and orientation");
    FilterState state = moved_state(3);
    const FilterState before = state;

    state.move_origin_to_camera(position_only);
    EXPECT_LT((state.world_cam_from_world().matrix() - before.world_cam_from_world().matrix())
                  .norm(),
              1e-12);
    for (int s = 0; s < state.num_slots(); ++s)
      EXPECT_LT((state.in_world(state.world_point(s)) - before.in_world(before.world_point(s)))
                    .norm(),
                1e-12);
    EXPECT_EQ(state.mean.t, Eigen::Vector3d::Zero());
    if (position_only)
      EXPECT_EQ(state.mean.R, before.mean.R);
    else
      EXPECT_EQ(state.mean.R, Eigen::Matrix3d::Identity());
    const int n = static_cast<int>(state.P.rows());
    EXPECT_LT(moved_error(before, state, Eigen::VectorXd::Zero(n), position_only).norm(), 1e-12);
    const int known = position_only ? 3 : 6;
    EXPECT_EQ(state.P.middleRows(6 - known, known).norm(), 0);
    EXPECT_EQ(state.P.middleCols(6 - known, known).norm(), 0);

    Eigen::MatrixXd J(n, n);
    const double h = 1e-6;
    for (int k = 0; k < n; ++k) {
      Eigen::VectorXd up = Eigen::VectorXd::Zero(n), down = up;
      up[k] = h;
      down[k] = -h;
      J.col(k) = (moved_error(before, state, up, position_only) -
                  moved_error(before, state, down, position_only)) /
                 (2 * h);
    }
    const Eigen::MatrixXd expected = J * before.P * J.transpose();
    EXPECT_LT((state.P - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff());
  }
}

// The published pose covariance folds in the state frame's error: it is world_view's pose part
// through central differences.
TEST(FilterState, WorldPoseCovarianceFoldsInTheStateFramesError) {
  const FilterState state = moved_state(7);
  const Eigen::MatrixXd F = world_view_jacobian(state).topRows<6>();
  const Eigen::Matrix<double, 6, 6> expected = F * state.P * F.transpose();
  const Eigen::Matrix<double, 6, 6> published = state.world_pose_covariance();
  EXPECT_LT((published - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.cwiseAbs().maxCoeff());
}

TEST(FilterState, PlusMovesEveryPartAndHoldsPointsShortOfInfinity) {
  FilterState state;
  state.add(4, anchor_along(Eigen::Vector3d::Zero(), {0, 1, 0}),
            params_of(0, 0, 0.5, Eigen::Vector3d::Zero()),
            Eigen::Matrix<double, FilterState::kPointSize, 6>::Zero(), PointParams::Ones());
  Eigen::VectorXd delta = Eigen::VectorXd::Zero(state.point_column(1));
  delta.head<3>() << 0, 0, 0.1;
  delta.segment<3>(3) << 1, 2, 3;
  delta.segment<3>(FilterState::kBiasColumn) << 0.01, 0.02, 0.03;
  delta[FilterState::kScaleColumn] = 0.05;
  delta.tail<6>() << 0.1, -0.1, -2, 0.2, 0.3, 0.4;  // the inverse depth past zero
  const FilterMean moved = state.mean.plus(delta, 1e-3);
  EXPECT_LT((moved.R - Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix()).norm(),
            1e-15);
  EXPECT_EQ(moved.t, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(moved.sensors.gyro_bias, Eigen::Vector3d(0.01, 0.02, 0.03));
  EXPECT_DOUBLE_EQ(moved.sensors.wheel_scale, 1.05);
  EXPECT_EQ(moved.params(0), params_of(0.1, -0.1, 1e-3, {0.2, 0.3, 0.4}));
}

// Considered camera parameters: their columns sit between the sensors' and the points'; a point
// hung on the pose and on them has the covariance of J = [G, G_camera] applied to theirs, plus
// its own; their own block returns to the calibration's after anything changed it.
TEST(FilterState, APointHangsOnTheConsideredCameraParameters) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal(0, 1);
  Eigen::MatrixXd camera_covariance(2, 2);
  camera_covariance << 4e-6, 1e-6, 1e-6, 9e-6;
  FilterState state(camera_covariance);
  ASSERT_EQ(state.num_camera_params(), 2);
  ASSERT_EQ(state.first_point_column(), FilterState::kCameraColumn + 2);
  constexpr int kFixed = FilterState::kCameraColumn + 2;  // the columns before the points
  ASSERT_EQ(state.P.rows(), kFixed);
  EXPECT_EQ(state.P.block(FilterState::kCameraColumn, FilterState::kCameraColumn, 2, 2),
            camera_covariance);
  const Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(kFixed, kFixed, [&] { return normal(rng); });
  state.P = A * A.transpose() + Eigen::MatrixXd::Identity(kFixed, kFixed);
  const Eigen::MatrixXd before = state.P;

  constexpr int kSize = FilterState::kPointSize;
  const Eigen::Matrix<double, kSize, 6> G = Eigen::Matrix<double, kSize, 6>::NullaryExpr(
      [&] { return normal(rng); });
  const Eigen::MatrixXd G_camera = Eigen::MatrixXd::NullaryExpr(kSize, 2, [&] { return normal(rng); });
  const PointParams own = params_of(0.1, 0.2, 0.3, {0.4, 0.5, 0.6});
  state.add(4, anchor_along(Eigen::Vector3d::Zero(), {1, 0, 0}), PointParams::Zero(), G, own,
            G_camera);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(kSize, kFixed);
  J.leftCols<6>() = G;
  J.middleCols(FilterState::kCameraColumn, 2) = G_camera;
  const int c = state.point_column(0);
  ASSERT_EQ(c, kFixed);
  const Eigen::MatrixXd point_covariance =
      J * before * J.transpose() + Eigen::MatrixXd(own.cwiseAbs2().asDiagonal());
  EXPECT_LT((state.P.block(c, c, kSize, kSize) - point_covariance).norm(),
            1e-12 * point_covariance.norm());
  EXPECT_LT((state.P.block(c, 0, kSize, kFixed) - J * before).norm(), 1e-12 * before.norm());
  EXPECT_EQ(state.P.block(0, c, kFixed, kSize), state.P.block(c, 0, kSize, kFixed).transpose());

  state.P.block(FilterState::kCameraColumn, FilterState::kCameraColumn, 2, 2).setZero();
  state.reset_considered_blocks();
  EXPECT_EQ(state.P.block(FilterState::kCameraColumn, FilterState::kCameraColumn, 2, 2),
            camera_covariance);
  // The camera's columns stay put as points come and go.
  state.remove(0);
  EXPECT_EQ(state.P.rows(), kFixed);
  EXPECT_EQ(state.P.block(FilterState::kCameraColumn, 0, 2, FilterState::kCameraColumn),
            before.block(FilterState::kCameraColumn, 0, 2, FilterState::kCameraColumn));
}

// A prior applied to a point's inverse depth by a Kalman update, then taken back: the state it
// started from, mean and covariance, everything the prior reached through the correlations.
TEST(FilterState, TakingBackAPriorUndoesItsUpdate) {
  FilterState state;
  for (int track : {3, 5})
    state.add(track, anchor_along(Eigen::Vector3d::Zero(), {1, 0.5 * track, 0}),
              params_of(0.01, -0.02, 0.3 + 0.1 * track, {0.01, 0.02, 0.03}),
              Eigen::Matrix<double, FilterState::kPointSize, 6>::Zero(), PointParams::Ones());
  randomise_covariance(&state, 11);
  state.mean.t << 0.5, -0.2, 1.0;
  state.mean.sensors.wheel_scale = 1.02;
  const FilterState before = state;

  const int c = state.point_column(1) + 2;
  const double prior_mean = 0.2, prior_variance = 0.25;
  const Eigen::VectorXd gain = state.P.col(c) / (state.P(c, c) + prior_variance);
  state.mean = state.mean.plus(gain * (prior_mean - state.mean.params(1)[2]), 1e-3);
  state.P -= gain * state.P.row(c);
  ASSERT_GT((state.P - before.P).norm(), 1e-3);

  // A prior looser than what the state holds cannot have been applied to it.
  const FilterState updated = state;
  EXPECT_FALSE(state.take_back_prior(c, prior_mean, 0.5 * state.P(c, c), 1e-3));
  EXPECT_EQ(state.P, updated.P);
  ASSERT_TRUE(state.take_back_prior(c, prior_mean, prior_variance, 1e-3));
  EXPECT_LT((state.P - before.P).norm(), 1e-10);
  EXPECT_LT((state.mean.R - before.mean.R).norm(), 1e-12);
  EXPECT_LT((state.mean.t - before.mean.t).norm(), 1e-12);
  EXPECT_LT((state.mean.sensors.gyro_bias - before.mean.sensors.gyro_bias).norm(), 1e-12);
  EXPECT_NEAR(state.mean.sensors.wheel_scale, before.mean.sensors.wheel_scale, 1e-12);
  EXPECT_LT((state.mean.points - before.mean.points).norm(), 1e-12);
}

// The wheels' scale considered: a step never moves it, and an update leaves the covariance among
// the considered states (the scale, the state frame's place, their cross-covariance) as it was,
// while the rest takes the Kalman update (Schmidt's: the rest's rows of P - K H P are the Kalman
// update's, the considered block is not).
TEST(FilterState, AConsideredWheelScaleNeverMovesAndKeepsItsCovariance) {
  FilterState state = moved_state(5);
  constexpr int kScale = FilterState::kScaleColumn;
  const double variance = 0.02 * 0.02;
  EXPECT_FALSE(state.wheel_scale_considered());
  state.consider_wheel_scale(variance);
  ASSERT_TRUE(state.wheel_scale_considered());
  EXPECT_EQ(state.P(kScale, kScale), variance);
  state.mean.sensors.wheel_scale = 1.01;
  ASSERT_GT(std::abs(state.P(kScale, FilterState::kOriginColumn)), 0.1);

  // A scalar measurement of the pose's first translation, 0.1 off.
  const int c = 3;
  const Eigen::VectorXd gain = state.P.col(c) / (state.P(c, c) + 1e-4);
  Eigen::VectorXd step = gain * 0.1;
  ASSERT_GT(std::abs(step[kScale]), 1e-6) << "the scale is not correlated with the measurement";
  state.hold_considered(&step);
  EXPECT_EQ(step[kScale], 0);
  EXPECT_EQ(step.segment<6>(FilterState::kOriginColumn).norm(), 0);
  EXPECT_EQ(step.head<6>(), (gain * 0.1).head<6>());
  const FilterMean moved = state.mean.plus(step, 1e-3);
  EXPECT_EQ(moved.sensors.wheel_scale, 1.01);
  EXPECT_NEAR(moved.t.x(), state.mean.t.x() + gain[c] * 0.1, 1e-15);

  const Eigen::MatrixXd held = state.considered_covariance();
  ASSERT_EQ(held.rows(), 7);  // the scale and the frame's six
  const Eigen::MatrixXd kalman = state.P - gain * state.P.row(c);
  state.P = kalman;
  ASSERT_GT((state.considered_covariance() - held).norm(), 1e-3);
  state.restore_considered_covariance(held);
  EXPECT_EQ(state.considered_covariance(), held);
  EXPECT_EQ(state.P(kScale, kScale), variance);
  EXPECT_EQ(state.P.row(c), kalman.row(c));
  EXPECT_EQ(state.P.col(kScale).head<6>(), kalman.col(kScale).head<6>());
}

// A new point's parameters about its anchor under the pose's error, against central differences:
// the perturbed pose's world ray expressed about the anchor made at the unperturbed one.
TEST(FilterState, RayPoseJacobianMatchesCentralDifferences) {
  const Eigen::Matrix3d R = so3::exp(Eigen::Vector3d(0.3, -0.7, 1.1));
  const Eigen::Vector3d t(0.4, -1.2, 2.5), origin(0.01, -0.02, 0.05);
  const Eigen::Vector3d direction = Eigen::Vector3d(0.3, 0.8, -0.5).normalized();
  const PointAnchor anchor = anchor_along(R.transpose() * (origin - t), R.transpose() * direction);
  const auto params_at = [&](const Eigen::Matrix<double, 6, 1>& error) {
    const Eigen::Matrix3d R_moved = so3::exp(error.head<3>()) * R;
    const Eigen::Vector3d t_moved = t + error.tail<3>();
    const Eigen::Vector3d d = R_moved.transpose() * direction;
    const double along = anchor.basis.col(0).dot(d);
    PointParams params;
    params << anchor.basis.col(1).dot(d) / along, anchor.basis.col(2).dot(d) / along, 0.5,
        R_moved.transpose() * (origin - t_moved) - anchor.origin;
    return params;
  };
  const Eigen::Matrix<double, 6, 6> G = ray_pose_jacobian(anchor, R, t, origin, direction);
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Eigen::Matrix<double, 6, 1> up = Eigen::Matrix<double, 6, 1>::Zero(), down = up;
    up[k] = h;
    down[k] = -h;
    const PointParams numeric = (params_at(up) - params_at(down)) / (2 * h);
    EXPECT_LT((G.col(k) - numeric).norm(), 1e-7 * (1 + numeric.norm())) << "column " << k;
  }
  EXPECT_LT(params_at(Eigen::Matrix<double, 6, 1>::Zero()).norm() - 0.5, 1e-12);
}

}  // namespace
}  // namespace omnisfm::sfm
