// The filter's propagation by the vehicle's predicted motion (odometry, gyro), in place of the
// random walk.

#include <algorithm>
#include <cmath>

#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/sfm/online_filter.h"
#include "so3.h"

namespace omnisfm::sfm {

bool OnlineFilter::process_frame(int frame, const std::vector<TrackPixel>& observations,
                                 const MotionPrediction& motion) {
  return process(frame, observations, &motion);
}

// With M = cam_from_previous_cam: R' = R_M R, t' = R_M t + t_M. For the left-perturbed pose error
// (dtheta, dt) and M's error (dm, dt_M):
//   dtheta' = R_M dtheta + dm,   dt' = R_M dt - [R_M t]x dm + dt_M,
// where M's error is B db + S ds from the gyro bias's error db and the wheel scale's ds
// (motion.bias_jacobian, wheel_scale_jacobian) plus the prediction's own noise. The bias walks; the
// scale and the points, in the world frame, do not move: only their cross-covariance with the
// pose turns.
void OnlineFilter::propagate(const MotionPrediction& motion) {
  const Eigen::Matrix3d R_M = motion.cam_from_previous_cam.linear();
  const Eigen::Vector3d t_M = motion.cam_from_previous_cam.translation();
  Eigen::Matrix<double, 6, 6> G = Eigen::Matrix<double, 6, 6>::Identity();
  FilterMean& mean = state_.mean;
  Eigen::MatrixXd& P = state_.P;
  constexpr int kBiasColumn = FilterState::kBiasColumn;
  const Eigen::Vector3d t_linearised =
      at_given_points() ? linearisation_points_.cam_from_world(previous_frame_).translation().eval()
                        : mean.t;
  G.block<3, 3>(3, 0) = -so3::skew(R_M * t_linearised);
  mean.R = R_M * mean.R;
  mean.t = R_M * mean.t + t_M;
  if (!bias_started_ && motion.bias_prior_variance > 0) {
    // The bias is unknown but for its prior; nothing is correlated with it yet.
    P.block<3, 3>(kBiasColumn, kBiasColumn) =
        motion.bias_prior_variance * Eigen::Matrix3d::Identity();
    bias_started_ = true;
  }
  distance_measured_ = distance_measured_ || motion.measures_distance;
  if (!scale_started_ && motion.wheel_scale_prior_variance > 0) {
    P(FilterState::kScaleColumn, FilterState::kScaleColumn) = motion.wheel_scale_prior_variance;
    if (!settings_.wheel_scale_from_images)
      state_.consider_wheel_scale(motion.wheel_scale_prior_variance);
    scale_started_ = true;
  }

  // P <- Phi P Phi^T with Phi = [F, G [B S], 0; 0, I, 0; 0, 0, I]: rows, then columns.
  Eigen::Matrix<double, 6, 6> F = Eigen::Matrix<double, 6, 6>::Zero();
  F.topLeftCorner<3, 3>() = R_M;
  F.bottomRightCorner<3, 3>() = R_M;
  Eigen::Matrix<double, 6, 4> coupling;
  coupling << motion.bias_jacobian, motion.wheel_scale_jacobian;
  const Eigen::Matrix<double, 6, 4> GC = G * coupling;
  const bool coupled = !GC.isZero();
  static_assert(FilterState::kScaleColumn == kBiasColumn + 3, "the sensors' states sit together");
  Eigen::MatrixXd top = F * P.topRows<6>();
  if (coupled) top.noalias() += GC * P.middleRows<4>(kBiasColumn);
  P.topRows<6>() = top;
  Eigen::MatrixXd left = P.leftCols<6>() * F.transpose();
  if (coupled) left.noalias() += P.middleCols<4>(kBiasColumn) * GC.transpose();
  P.leftCols<6>() = left;
  P.topLeftCorner<6, 6>() += G * motion.covariance * G.transpose();
  P.block<3, 3>(kBiasColumn, kBiasColumn).diagonal().array() += motion.bias_walk_variance;
}

OnlineFilter::BeforePropagation OnlineFilter::before_propagation() const {
  constexpr int kBiasColumn = FilterState::kBiasColumn;
  return {state_.mean, state_.P.topRows<6>(), state_.P.block<3, 3>(kBiasColumn, kBiasColumn)};
}

void OnlineFilter::restore(const BeforePropagation& before) {
  state_.mean = before.mean;
  state_.P.topRows<6>() = before.pose_rows;
  state_.P.leftCols<6>() = before.pose_rows.transpose();
  state_.P.block<3, 3>(FilterState::kBiasColumn, FilterState::kBiasColumn) = before.bias_block;
}

MotionPrediction OnlineFilter::with_rotation_of(const MotionPrediction& given,
                                                MotionPrediction walk) {
  walk.cam_from_previous_cam.linear() = given.cam_from_previous_cam.linear();
  walk.covariance.topLeftCorner<3, 3>() = given.covariance.topLeftCorner<3, 3>();
  walk.bias_jacobian.topRows<3>() = given.bias_jacobian.topRows<3>();
  return walk;
}

// The frame's estimated motion, last_motion_, has the error of the two poses it joins; the
// current pose's covariance stands for both (it holds the drift since the state's origin last
// moved, more than a frame's): a conservative variance, under which a sensor that agrees scores
// well below its degrees of freedom and a failed one (a frozen wheel's 3 cm on the long drive, a
// stuck gyro's turn) tens a frame. Once a fallback keeps the gyro's rotation, the estimate leans
// on the gyro and judges it less sharply; a gyro that fails then too is still caught by the whole
// prediction's misfit, which refuses both.
void OnlineFilter::judge_motion_parts(const MotionPrediction& given) {
  const Eigen::Matrix<double, 6, 6> estimate = state_.P.topLeftCorner<6, 6>();
  const double cap = 2 * settings_.outlier_chi2;
  if (const int axes = measured_rotation_axes(given, settings_.rotation_walk_sigma); axes > 0) {
    const Eigen::Vector3d error =
        so3::log(last_motion_.linear() * given.cam_from_previous_cam.linear().transpose());
    const Eigen::Matrix3d variance =
        given.covariance.topLeftCorner<3, 3>() + estimate.topLeftCorner<3, 3>();
    const double score = error.dot(variance.ldlt().solve(error));
    rotation_misfit_sum_ = std::clamp(rotation_misfit_sum_ + score - axes, 0.0, cap);
  }
  const double step = last_motion_.translation().norm();
  if (given.measures_distance && step > 0) {
    const Eigen::Vector3d along = last_motion_.translation() / step;
    const double error = step - given.cam_from_previous_cam.translation().norm();
    // The wheels' scale's own error too, the same in every frame (a considered state).
    const double scale_term = along.dot(given.wheel_scale_jacobian.tail<3>());
    const double variance =
        along.dot(
            (given.covariance.bottomRightCorner<3, 3>() + estimate.bottomRightCorner<3, 3>()) *
            along) +
        scale_term * scale_term * state_.P(FilterState::kScaleColumn, FilterState::kScaleColumn);
    distance_misfit_sum_ =
        std::clamp(distance_misfit_sum_ + error * error / variance - 1, 0.0, cap);
  }
}

MotionPrediction OnlineFilter::constant_velocity() const {
  MotionPrediction prediction = random_walk();
  prediction.cam_from_previous_cam = last_motion_;
  return prediction;
}

MotionPrediction OnlineFilter::random_walk() const {
  MotionPrediction prediction;
  prediction.covariance.topLeftCorner<3, 3>().diagonal().setConstant(settings_.rotation_walk_sigma *
                                                                     settings_.rotation_walk_sigma);
  prediction.covariance.bottomRightCorner<3, 3>().diagonal().setConstant(
      settings_.translation_walk_sigma * settings_.translation_walk_sigma);
  return prediction;
}

void OnlineFilter::refuse_motion_at(int frame) {
  ++refused_motions_;
  if (motion_refused_) motion_refused_(frame);
}

std::vector<OnlineFilter::Measurement> OnlineFilter::propagate_checked(
    const std::map<int, Eigen::Vector2d>& seen, const MotionPrediction** motion) {
  const MotionPrediction& given = **motion;
  // A prediction that starts a sensor's state is not taken back (the first frames have no
  // established points to judge it by anyway), nor one a consistency study linearises.
  const bool starts_a_state = (!bias_started_ && given.bias_prior_variance > 0) ||
                              (!scale_started_ && given.wheel_scale_prior_variance > 0);
  if (starts_a_state || at_given_points()) {
    propagate(given);
    refused_in_a_row_ = 0;
    return measurements_of(seen);
  }
  const BeforePropagation before = before_propagation();
  const bool distance_measured = distance_measured_;
  propagate(given);
  std::vector<Measurement> measurements = measurements_of(seen);
  const double bound = settings_.outlier_chi2;
  double misfit = motion_misfit(seen, measurements);
  bool gross = misfit > bound;
  // Where the sensors leave part of the motion to the walk, each point's prediction is no test of
  // them. Roll and pitch left to it (the odometry without a gyro): a tilt stands for a distance
  // the prediction lacks, and each point fits on its own (a frozen wheel's median score 0.2-1.2
  // on the long drive). The translation left to it (a gyro alone): the walk's own misfit, which
  // grows with the map vision alone, is no fault of the gyro's (on the 120 m drive a clean
  // gyro's motion was refused in a third of the frames). There the images' agreement on one
  // pose after a trial update judges the prediction too: the upper quartile of the established
  // points' scores (0.6-1.6 when consistent; 4-20 with the wheel frozen, 26 and 87 in a stuck
  // gyro's first frames on the rover), gross beyond chi-square's 1 - 1e-3 quantile, where a
  // quarter of the points lie where one in a thousand should. A consistent prediction's quartile
  // stays below kConsistentAfterUpdate, as its median below kConsistentMisfit.
  double consistent = kConsistentMisfit;
  if (!std::isnan(misfit) && !measures_whole_motion(given, settings_.rotation_walk_sigma)) {
    const double after = misfit_after_update(measurements, 0.75);
    if (!std::isnan(after)) {
      // Points that do not project at the prediction count against it whatever is left.
      const bool walk_translation = !given.measures_distance && !std::isinf(misfit);
      misfit = walk_translation ? after : std::max(misfit, after);
      gross = (!walk_translation && gross) || after > kGrossAfterUpdate;
      // A trial update's scores follow the tracks' noise itself, which may be well below the
      // stated (0.6-1.6 for the quartile on the drive and the rover at 0.2 px, 0.3 stated) or up
      // to twice its variance before the filter takes it: held to chi-square's quartile at the
      // stated noise, a clean sensor at 0.3 px was refused for good.
      consistent = kConsistentAfterUpdate * noise_ratio();
    }
  }
  // A sensor that fails for good (a wheel that stops counting, a gyro stuck at zero) may misfit by
  // less than the bound each frame, but frame after frame: its excess over a consistent
  // prediction's median (measured 0.1-0.3 on the rover, against 5-17 with the wheel frozen) is
  // summed (a cumulative-sum test, bounded so that a sensor that agrees again is taken back within
  // about 15 frames); a gross misfit is the single-frame test's, frame after frame too where the
  // fault is larger (35-145 a frame with the wheel frozen on the long drive). After a refused
  // frame, the sensors are taken back only once they fit as a consistent prediction does: a
  // fault that misfits grossly and then by less is one fault (on the rover at seed 1, a frozen
  // wheel without a gyro misfit grossly for 14 frames, then by 23, and taken, rejected 92 good
  // tracks).
  if (!std::isnan(misfit) && !gross) {
    sensor_misfit_sum_ = std::clamp(sensor_misfit_sum_ + misfit - consistent, 0.0, 2 * bound);
    if (sensor_misfit_sum_ == 0) suspect_frames_.clear();
  }
  const bool still_at_odds = refused_in_a_row_ > 0 && misfit > consistent;
  const bool lasting = !gross && (sensor_misfit_sum_ > bound || still_at_odds);
  if (!gross && !lasting) {
    // The last few: a sum that hovers above 0 over an endless drive would otherwise keep them all.
    constexpr std::size_t kMaxSuspectFrames = 30;
    if (sensor_misfit_sum_ > 0) suspect_frames_.push_back(frame_);
    if (suspect_frames_.size() > kMaxSuspectFrames) suspect_frames_.pop_front();
    refused_in_a_row_ = 0;
    if (given.measures_distance && sensor_misfit_sum_ == 0)
      consistent_step_m_ = given.cam_from_previous_cam.translation().norm();
    return measurements;
  }

  restore(before);
  distance_measured_ = distance_measured;
  // A frame's gross error is the sensor's alone, and the motion goes on as it went. A fault that
  // lasts, summed or gross frame after frame, leaves no motion to go on from that the sensor did
  // not distort, and the frame takes the random walk, as the images alone would: the constant
  // velocity, fed back its own estimates with no distance measured, diverged within 30 frames on
  // the long drive. Where the walk does not fit either (a step large against the walk's sigma),
  // the constant velocity is tried before the sensors' motion is kept.
  std::vector<MotionPrediction> fallbacks;
  if (gross && refused_in_a_row_ == 0) {
    fallbacks = {constant_velocity()};
  } else {
    // Once the wheels are refused nothing but the walk weighs the map's scale, which settles
    // where a frame's step is about two of the walk's sigmas (docs/shape-from-motion.md, "Endless
    // sequences"): a walk paced by the last step the wheels measured unsuspected keeps the scale
    // they had (the long drive with its gyro stuck halfway 0.56-0.63 % after a rigid alignment
    // over 600 m, where the set walk's 5 cm let the scale grow 30 %). Where it does not fit (the
    // vehicle changed pace), the set walk, then the constant velocity.
    fallbacks = {random_walk(), constant_velocity()};
    MotionPrediction paced = random_walk();
    if (consistent_step_m_ > 0) {
      paced.covariance.bottomRightCorner<3, 3>() =
          std::pow(consistent_step_m_ / 2, 2) * Eigen::Matrix3d::Identity();
      fallbacks.insert(fallbacks.begin(), paced);
    }
    // Where the wheels' distances are at odds with the frames' estimated motion and the gyro's
    // rotations are not (judge_motion_parts), the gyro's rotation with the paced walk goes first.
    const bool rotation_at_odds = rotation_misfit_sum_ > bound;
    const bool distance_at_odds = distance_misfit_sum_ > bound;
    if (distance_at_odds && !rotation_at_odds &&
        measured_rotation_axes(given, settings_.rotation_walk_sigma) == 3)
      fallbacks.insert(fallbacks.begin(), with_rotation_of(given, paced));
  }
  std::vector<Measurement> alternative;
  bool fits = false;
  for (MotionPrediction& fallback : fallbacks) {
    restore(before);
    distance_measured_ = distance_measured;
    fallback.bias_walk_variance = given.bias_walk_variance;  // the gyro's bias walks on meanwhile
    propagate(fallback);
    alternative = measurements_of(seen);
    // The prediction, as loose as the random walk, fits each measurement alone; the images must
    // also agree on one pose.
    fits = motion_misfit(seen, alternative) <= bound && fits_after_update(alternative);
    if (fits) {
      fallback_motion_ = fallback;
      break;
    }
  }
  if (!fits) {
    // The images agree with none: they are the suspects, and the sensors' motion stands.
    restore(before);
    distance_measured_ = distance_measured;
    propagate(given);
    refused_in_a_row_ = 0;
    return measurements;
  }
  // The frames that led up to a lasting fault took the sensors' motion; too late for the filter,
  // but their readings are as wrong, and the batch leaves them out too.
  if (lasting)
    for (const int suspect : suspect_frames_) refuse_motion_at(suspect);
  suspect_frames_.clear();
  refuse_motion_at(frame_);
  ++refused_in_a_row_;
  *motion = &fallback_motion_;
  return alternative;
}

}  // namespace omnisfm::sfm
