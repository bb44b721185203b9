#pragma once
// The online filter's estimate (online_filter.h): one mean and one covariance over it, and the
// slots that map the live tracks to their points, as MRPT's CKalmanFilterCapable keeps one state
// vector with landmark accessors.
//
// Mean: cam_from_world (R, t), the vehicle's sensors' states, and per slot a live track's point
// in inverse depth with its anchor in the state (Civera, Davison and Montiel's six parameters):
// two angles across its first ray and an inverse distance along it, then the offset of that ray's
// origin from where it was first placed. A new point then depends on the pose it was first seen
// from linearly and without its unknown depth: with the origin fixed, the pose's translation
// error entered the angles divided by the depth guess (2 m for a point 0.5-20 m away), which
// left the published pose covariance several times overconfident (eval::rover_pose_consistency).
// Covariance columns: the pose 0-5 (the rotation's error a left perturbation, R = exp(dtheta) R,
// then the translation's), the gyro's bias 6-8, the wheels' scale 9, the state frame's place in
// the world 10-15 (its rotation, a left perturbation in the world, then its position;
// move_origin_to_camera), the camera parameters the filter considers
// (FilterSettings::camera_uncertainty; none by default), then 6 per slot.
//
// The state frame's place in the world, the considered camera parameters and, unless the images
// are to inform it, the wheels' scale are Schmidt's consider states: their error is in the
// covariance, correlated with the rest, but never estimated. The mean holds no entry for them
// (the frame's place is world_from_state()), and each update puts the covariance among them back
// as it was (considered_covariance). The camera stays as given, its block the
// calibration's covariance: a sequence may well be unable to tell a mirror's tilt from the
// rig's attitude, and an estimate that drifts with the latter would then bend every later
// measurement. Nothing observes where the state's frame is in the world, and an estimate of it
// would move with the little the updates wrongly learn of the rotation about it
// (FilterSettings::origin_follows_camera, origin_turns_with_camera), while its error, and how
// that error goes with the rest, is what the published pose covariance needs.

#include <Eigen/Geometry>
#include <map>
#include <vector>

namespace omnisfm::sfm {

// A point's parameters about its anchor: angles across its ray (0, 1), inverse distance along it
// (2), the ray origin's offset in the state's frame (3-5).
using PointParams = Eigen::Matrix<double, 6, 1>;
using PointJacobian = Eigen::Matrix<double, 3, 6>;  // world point per parameter

// What the filter estimates of the vehicle's sensors, at which its next prediction is made.
struct SensorStates {
  Eigen::Vector3d gyro_bias{0, 0, 0};  // rad/s about the body's axes
  // The odometry's distances are multiplied by this on top of MotionSensors::odometry_scale.
  double wheel_scale = 1;
};

// A point's reference: where its first ray started as first placed (the state's offset moves it),
// and a basis whose first column is that ray's direction (world frame).
struct PointAnchor {
  Eigen::Vector3d origin{0, 0, 0};
  Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();
  int updates = 0;  // accepted updates the point has taken part in

  // The world point of parameters about this anchor, and its derivative with respect to them.
  Eigen::Vector3d world_point(const PointParams& params, PointJacobian* J_params = nullptr) const;
  // The parameters of a world point with the origin where it was first placed: world_point's
  // inverse at a zero offset.
  PointParams params_of(const Eigen::Vector3d& world_point) const;
};

// How a new point's parameters about `anchor` move with some errors, given how they move its
// first ray in the world frame (a column per error): the angles with the direction across the
// ray, the origin's offset with the origin, the depth not at all.
Eigen::Matrix<double, 6, Eigen::Dynamic> ray_parameters_jacobian(
    const PointAnchor& anchor, const Eigen::Matrix<double, 3, Eigen::Dynamic>& direction_moves,
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& origin_moves);

// How a new point's parameters about `anchor` move with the error of the pose (R, t) it was seen
// from (the rotation's a left perturbation, then the translation's), its ray leaving the camera at
// origin along direction (camera frame): the ray's origin moves with both, its direction turns
// with the rotation, and neither depends on the depth, whose row is zero.
Eigen::Matrix<double, 6, 6> ray_pose_jacobian(const PointAnchor& anchor, const Eigen::Matrix3d& R,
                                              const Eigen::Vector3d& t,
                                              const Eigen::Vector3d& origin,
                                              const Eigen::Vector3d& direction);

struct FilterMean {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  SensorStates sensors;
  Eigen::VectorXd points;  // FilterState::kPointSize per slot

  // Moved by `delta`, in the covariance's columns (the rotation to exp(delta's first three) R),
  // each inverse depth held at min_inverse_depth or beyond: noise can push a barely-parallaxed
  // point past infinity, and it is held far away instead.
  FilterMean plus(const Eigen::VectorXd& delta, double min_inverse_depth) const;
  Eigen::Isometry3d cam_from_world() const;
  PointParams params(int slot) const;
};

// add() and remove() keep the slots, the mean's points and the covariance in step.
class FilterState {
 public:
  static constexpr int kBiasColumn = 6;
  static constexpr int kScaleColumn = 9;
  static constexpr int kOriginColumn = 10;  // the state frame's rotation, then its position
  static constexpr int kCameraColumn = 16;
  static constexpr int kPointSize = 6;

  // `camera_covariance`: of the considered camera parameters (0 x 0: none).
  explicit FilterState(const Eigen::MatrixXd& camera_covariance = Eigen::MatrixXd());

  int num_camera_params() const { return static_cast<int>(camera_covariance_.rows()); }
  int first_point_column() const { return kCameraColumn + num_camera_params(); }
  int point_column(int slot) const { return first_point_column() + kPointSize * slot; }
  // The considered camera parameters' and wheels' scale's own blocks set to the calibration's, for
  // a covariance made anew (the smoothed start's restart, before the state's frame has moved).
  void reset_considered_blocks();
  // From now on the wheels' scale is a consider state too, its variance `variance`
  // (FilterSettings::wheel_scale_from_images).
  void consider_wheel_scale(double variance);
  bool wheel_scale_considered() const { return wheel_scale_variance_ > 0; }
  // A step in the covariance's columns with the considered states' entries zeroed: they never move.
  void hold_considered(Eigen::VectorXd* step) const;
  // The covariance among all the considered states, their cross-covariances included, which
  // Schmidt's update keeps as it was: taken before an update and put back after it.
  Eigen::MatrixXd considered_covariance() const;
  void restore_considered_covariance(const Eigen::MatrixXd& block);

  FilterMean mean;
  Eigen::MatrixXd P;

  int num_slots() const { return static_cast<int>(slot_track_.size()); }
  // The slot of a track's point; -1 when the state holds none.
  int slot_of(int track) const;
  int track_of(int slot) const { return slot_track_[slot]; }
  const std::vector<int>& slot_tracks() const { return slot_track_; }
  PointAnchor& anchor(int slot) { return anchors_[slot]; }
  const PointAnchor& anchor(int slot) const { return anchors_[slot]; }
  Eigen::Vector3d world_point(int slot) const {
    return anchors_[slot].world_point(mean.params(slot));
  }

  // A new slot, the last, for a track's point at `params` about `anchor`. The point hangs on the
  // pose and the considered camera parameters: its error is G times the pose's plus G_camera
  // times theirs (kPointSize x num_camera_params(); ignored without them) plus its own
  // (independent, `own_sigma` per parameter).
  int add(int track, const PointAnchor& anchor, const PointParams& params,
          const Eigen::Matrix<double, kPointSize, 6>& G, const PointParams& own_sigma,
          const Eigen::MatrixXd& G_camera = Eigen::MatrixXd());
  // The slot's point leaves; the last slot moves into its place.
  void remove(int slot);
  // Where the state's frame sits in the world: the mean's pose and points are in it.
  const Eigen::Isometry3d& world_from_state() const { return world_from_state_; }
  Eigen::Vector3d in_world(const Eigen::Vector3d& state_point) const {
    return world_from_state_ * state_point;
  }
  // Moves the state's frame to the camera: the pose becomes the identity, known exactly, and its
  // error passes to the points' anchors, whose errors are from then on relative to the camera,
  // and to the state frame's. With `position_only`, the frame keeps its axes and only the pose's
  // translation goes.
  void move_origin_to_camera(bool position_only = false);
  // cam_from_world in the world, and the covariance of its error (rotation, then translation),
  // the state frame's error folded in.
  Eigen::Isometry3d world_cam_from_world() const;
  Eigen::Matrix<double, 6, 6> world_pose_covariance() const;
  // Takes a Gaussian prior, N(prior_mean, prior_variance) on a point's `column`, back out of
  // the mean and the covariance: the state as if that prior had never been applied, exact for a
  // linear model (the information form's subtraction, by Woodbury). Inverse depths stay at
  // min_inverse_depth or beyond, as in FilterMean::plus. False, changing nothing, unless the
  // column's variance is below prior_variance (measurements since have added to the prior).
  bool take_back_prior(int column, double prior_mean, double prior_variance,
                       double min_inverse_depth);

 private:
  Eigen::MatrixXd camera_covariance_;
  Eigen::Isometry3d world_from_state_ = Eigen::Isometry3d::Identity();
  double wheel_scale_variance_ = 0;  // > 0 while the wheels' scale is considered
  std::vector<int> considered_columns() const;
  std::vector<PointAnchor> anchors_;  // per slot
  std::vector<int> slot_track_;
  std::map<int, int> track_slot_;
};

}  // namespace omnisfm::sfm
