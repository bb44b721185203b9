#pragma once
// The online estimator of the paper: an extended Kalman filter over the current camera pose and
// the 3D points of the live tracks.
//
// State: cam_from_world (R, t; the rotation's error is a left perturbation R = exp(dtheta) R, so
// any attitude works), the gyro's bias (a random walk) and the wheels' scale (a correction of the
// calibrated one, constant), each coupled to the pose by the predictions that integrate its sensor
// (with no such sensor it stays out of every product), and one 3D world point per live track.
// (FilterState, filter_state.h, holds it with its covariance.) The first frame fixes the gauge:
// its pose is the identity, known exactly. The state's frame follows the camera
// (FilterSettings::origin_follows_camera, origin_turns_with_camera): its place in the world is
// kept outside the state and its error is a considered state, so that every pose, point and
// covariance the filter hands out is in the first frame's world. Propagation keeps the estimate and inflates the pose
// covariance by a random walk, or, when the vehicle's sensors predict the motion, moves the pose by
// that prediction and adds its covariance. A new track's point starts on a sphere around the camera along its
// ray: very uncertain along the ray, certain across it. Points are held in inverse depth about
// their first ray (two angles across it, one inverse distance along it, and where that ray
// starts: filter_state.h), where a depth that is barely known stays well approximated by a
// Gaussian and never crosses behind the camera. The
// measurement update uses the noncentral projection's analytic Jacobians, iterated (a damped
// Gauss-Newton on the posterior cost, started from the established points' update when new
// points are measured, else from the posterior's minimum along the pose's direction of the
// prior; with the vehicle's sensors predicting the motion, from the prediction, relinearised only
// where its linear model misses: FilterSettings::predicted_settle_sigmas); afterwards, if the largest residual exceeds the outlier threshold, that track is
// discarded and the update re-run from the propagated estimate, until none does. A track
// that is not observed in a frame has ended and leaves the state, with the wheels' scale a state
// its depth prior taken back out of the rest (FilterSettings::take_back_depth_priors), so the per-frame cost stays
// bounded however long the sequence.
//
// The smoothed start: while every depth is still the initialisation's guess, each update
// linearises far from the truth, and an EKF keeps those errors (the first frames' poses and the
// points' covariances). After the first smoothed_start_frames frames, the filter solves its own
// model over them exactly (Ceres' Levenberg-Marquardt over all their poses and points: the
// measurements, the depth priors and the motion priors) and restarts from that solution, its covariance the
// information's inverse marginalised onto the current pose and the live points.

#include <Eigen/Geometry>
#include <deque>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/core/track_observation.h"
#include "omnisfm/sfm/camera_prior.h"
#include "omnisfm/sfm/filter_state.h"

namespace omnisfm::sfm {

// How the filter tells a track that went wrong from one it has not converged on yet.
enum class OutlierTest {
  // Each measurement's residual after the update against its own covariance (the measurement
  // noise less what the update explained, from the innovation covariance the filter already
  // forms): chi-square, 2 degrees of freedom, beyond outlier_chi2. A new point's residual is
  // judged against how little its first update could explain, an established one's against the
  // noise: the same test at any pixel_sigma.
  kChiSquare,
  // The paper's: the largest residual after the update beyond outlier_threshold_px.
  kPixels,
};

// When the filter's state moves its origin to the camera (FilterSettings::origin_follows_camera).
enum class OriginFollowsCamera {
  kNever,        // the first frame's, throughout
  kVisionAlone,  // in frames propagated by the random walk, not by the vehicle's sensors
  kAlways,
};

// Whether the state's frame, as it moves to the camera, takes the camera's orientation too
// (FilterSettings::origin_turns_with_camera).
enum class OriginTurnsWithCamera {
  kNever,        // its position only: the first frame's axes throughout
  kWithSensors,  // in frames whose whole motion (rotation and distance) the sensors measured
  kAlways,
};

struct FilterSettings {
  // The tracks' noise, pixels per coordinate: the filter's measurement noise, and with motion
  // sensors the fused batch's too (fused_pipeline.h); with measure_noise, where the tracks are
  // well noisier, the noise measured instead (OnlineFilter::pixel_sigma()). Vision alone over
  // long drives with a noncentral rig the orientation is best well above the tracks' noise and
  // worst at the noise itself: 0.2 px tracks on the 600 m drive, seeds 1-24, 1.41 deg mean error
  // (1.98 at most) at 0.4, 1.56 (2.51) at 0.3, 1.96 at 0.2 over seeds 1-12; 0.1 px tracks do best
  // at 0.3, share/omnisfm/cameras/equiangular.ini at 0.6, and central rigs barely change
  // (docs/shape-from-motion.md, "Endless sequences"). The outlier test widens with it.
  double pixel_sigma = 0.3;
  // Under the chi-square outlier test, whether the filter measures the tracks' noise and takes it
  // where it is well beyond pixel_sigma, for its measurement noise (and so the covariance it
  // publishes) and its outlier test: a noise understated by half rejected good tracks by the
  // dozen. From the median of the established points' outlier scores over the last 400
  // measurements, against chi-square(2)'s median (2 ln 2): taken where the variance it implies
  // is more than twice pixel_sigma's, let go below 1.5 times, never below pixel_sigma and at
  // most 10 times it. The smoothed start measures it from its window's residuals.
  bool measure_noise = true;
  double rotation_walk_sigma = 0.05;     // radians per frame
  double translation_walk_sigma = 0.05;  // metres per frame
  double initial_depth = 2.0;            // radius of the initialisation sphere, metres
  double inverse_depth_sigma = 0.5;      // along the ray, 1/metres
  OutlierTest outlier_test = OutlierTest::kChiSquare;
  // chi-square(2)'s 1 - 1e-6 quantile: in a sequence of a million measurements, one good one
  // rejected by chance.
  double outlier_chi2 = 27.63;
  double outlier_threshold_px = 2.0;  // with OutlierTest::kPixels
  // How far a pixel may be from a solution that explains it, where a whole window is solved (the
  // smoothed start, the batch's re-test): outlier_threshold_px, or with the chi-square test
  // sqrt(outlier_chi2) pixel_sigmas.
  double residual_limit_px() const;
  // Also reject, before the update, a measurement whose innovation lies beyond this squared
  // Mahalanobis distance of its predicted covariance: a track that slides to a nearby feature
  // jumps by a few pixels, which the update alone can absorb. 0 turns the gate off.
  double innovation_gate_chi2 = 0.0;
  // 1: the classic EKF; more: the iterated EKF, at most this many linearisations, stopping once
  // an iterate's predicted pixels move, or differ from the last linearisation's prediction, by
  // less than 3 % of pixel_sigma (predicted_settle_sigmas with the sensors' prediction). Steps
  // are damped when the posterior cost falls short of the linear model's prediction. Under the
  // random walk only: new points' depths make the first updates strongly nonlinear, so with more
  // than 2, frames with new points start from the established points' update; in frames without
  // new points, the first linearisation point is the posterior's minimum along the pose (one
  // Gauss-Newton step in six parameters), where one linearisation usually settles.
  int update_iterations = 8;
  // In frames the random walk propagates (vision alone), linearise each update once, at the
  // constant-velocity prediction (the propagated pose moved by the last updated frame's motion),
  // instead of iterating toward the frame's own minimum; update_iterations then applies only until
  // a frame has been updated, and in frames the sensors propagate. That minimum, the posterior's
  // mode, is biased in the square of the pixels' noise: on the long drive at 0.2 px each step comes
  // out 0.12-1.5 % long (bench/update_bias), which grows the map vision alone to 3.5 times the
  // truth's over 600 m, and through a noncentral mirror a map at the wrong scale tilts. Linearised
  // at the constant velocity the map keeps the scale the new points' depth priors gave it
  // (initial_depth), near the truth's where the scene is about initial_depth away: the drive's map
  // stays at 0.93-0.95 of the truth's, the tilt's mean over seeds stays at zero over the first
  // 2,000 frames (+1.6 deg at 600 m, -3.4 iterated), and the rover's map is 0.85-1.18 times the
  // truth's (5.6-6.6 iterated), but the lab's and crane's 0.59-0.66 (iterated 1.14-1.28 and
  // 3.5-3.9). The orientation's random walk over long drives remains (docs/shape-from-motion.md,
  // "Endless sequences"). With the sliding window, the frame after each of its solves is linearised
  // at a motion that holds the solve's correction too. Off by default: on with the other settings
  // as they are, ten tests fail, among them the lab's and crane's held-scale pose-graph NEES (8.0
  // and 12.6, 82 and 65 % inside, against 4.4 and 9.3) and tracks with their noise understated 20
  // times, of which it rejects every one (docs/shape-from-motion.md, "Endless sequences").
  bool linearise_at_constant_velocity = false;
  // With the motion predicted by the vehicle's sensors, the update starts at the prediction and
  // relinearises only where its linear model missed the new iterate's pixels by more than this
  // many pixel_sigmas (under the random walk: 0.03, from the posterior's minimum along the pose).
  // Relinearising at points that the frame's own measurements chose gains information along the
  // scale that a few centimetres of mirror barely show: over rover seeds 1-25 with the wheel's
  // scale estimated, the pose's mean NEES is 5.8 (92.6 % inside the 95 % bound) at 0.3 and at 1,
  // 7.4 at 0.1 and 12.8 at 0.03 (eval::rover_pose_consistency; 6 is honest), measured with the
  // depth priors kept (taken back: 5.82 and 92.7 % at 0.3).
  double predicted_settle_sigmas = 0.3;
  // When to move the state's origin to the camera: whenever the camera is further from it than
  // half the live points' median distance (the state frame's place in the world kept outside the
  // state, its error a considered state: filter_state.h). Nothing observes where the world's origin is,
  // yet each update gains a little information on the rotation about it (its Jacobians at each
  // frame's estimate annihilate another direction than the covariance was built around), and a
  // correction of that rotation moves the camera by its distance from the origin.
  // - Vision alone, on the 600 m drive at seed 1, that moved the camera 3.5 cm per frame
  //   backwards through each turn: the direction of travel 67 deg off over the drive, 8-10 % of
  //   the distance after a similarity alignment at seeds 1-3. With the origin following it,
  //   0.2 deg and 0.18-0.38 %. The rover's online error fell from 0.066-0.090 % to
  //   0.022-0.029 % (seeds 1-3). Moved before every frame instead, the crane's doubled
  //   (0.12-0.16 % to 0.24-0.56 %, seeds 1-6), where the threshold leaves it as it was.
  // - With odometry and gyro, the first frame's origin leaves the gyro's small drift honest only
  //   near it: on the 600 m drive at seed 1 (wheels' scale considered), the rotation's error grew
  //   to 10 deg while its published sigma shrank to 0.11 deg (mean NEES per 5,000 frames 15 / 174
  //   / 1,804 / 15,488). The gyro alone drifts 0.8 deg there, honestly; the images' updates, far
  //   from the origin, lent the rotation information it does not have. With the origin
  //   following the camera's position: 2.5 / 2.3 / 9.1 / 17, 0.26 % of the distance after a
  //   rigid alignment (0.60 % with it left behind); following its orientation too
  //   (origin_turns_with_camera): 2.7 / 3.9 / 4.6 / 4.3, 0.46 %.
  OriginFollowsCamera origin_follows_camera = OriginFollowsCamera::kAlways;
  // As the state's frame moves to the camera, it takes the camera's orientation too: the pose
  // becomes the identity, known exactly, and the rotation's error passes to the points and to
  // the frame's place in the world (a considered state: filter_state.h), which no update then
  // narrows. With its position alone, each update still gained a little information on the
  // rotation, the orientation's sigma stopped growing and the published covariance grew
  // overconfident over long drives. On the 600 m drive with odometry and gyro, seeds 1-6, mean
  // NEES over the last 5,000 frames 4.3 / 4.9 / 1.9 / 7.8 / 2.3 / 16 (17 / 26 / 3.0 / 32 / 27 /
  // 41 with the position alone; 6 when honest), the orientation's sigma 5.1 deg at the end where
  // it stayed at 1.5, and the drive 0.15-0.46 % off after a rigid alignment, mean orientation
  // error 0.9-2.5 deg (0.13-0.30 %, 0.9-1.7 deg). Vision alone it made the orientation worse
  // (seed 2: 7.95 deg against 2.07 over 600 m), and so it did with a lone sensor (over 600 m at
  // seed 1, a gyro alone 7.3 deg against 1.8, the wheels alone 9.8 against 2.0), hence the
  // default turns it only where the sensors measured the whole motion.
  OriginTurnsWithCamera origin_turns_with_camera = OriginTurnsWithCamera::kWithSensors;
  // Frames solved exactly before the filter runs on (see above); 0 for the plain filter.
  int smoothed_start_frames = 20;
  // With a gyro: estimate its bias as a state (else its prior inflates each prediction's rotation
  // noise, as if the bias were new in every frame; motion_prediction.h).
  bool estimate_gyro_bias = true;
  // With odometry: estimate a correction of the wheels' scale as a state, within
  // OdometryNoise::scale_sigma of the calibration (else the calibration is taken as exact). Over
  // rover seeds 1-50 with the simulated wheel reading 1.5 % long, the pose's mean NEES is 5.6
  // (92.7 % inside the 95 % bound); taking the calibration as exact, 110 over seeds 1-25.
  bool estimate_wheel_scale = true;
  // With the wheels' scale a state: whether the images' updates move it. Off (the default), it is
  // estimated over the smoothed start's window only (without a smoothed start it stays at the
  // calibration's), then carried as a Schmidt consider state
  // (filter_state.h): its error, OdometryNoise::scale_sigma, is in every covariance the filter
  // publishes, with its correlations, but no update moves or narrows it. What the images say of
  // the scale through a few centimetres of mirror is too little for an online filter to weigh
  // right: estimated, the wheels' scale followed the images' own over the 600 m drive (0.949 +-
  // 0.0015 at seed 1 for a true 0.985), the mean NEES over the last 5,000 frames was 51 and the
  // drive 0.69 % off after a rigid alignment; considered, 4.3 and 0.46 %. (With the state's
  // frame following the camera's position only: 0.950 and 0.917 +- 0.0014 at seeds 1 and 2, NEES
  // 77 and 542, 0.59 % and 1.32 %; considered, 17 and 26, 0.26 % and 0.28 %.) The batch
  // (fused_pipeline.h), which solves all frames together, estimates it from the images, and
  // from GPS where there is any.
  bool wheel_scale_from_images = false;
  // With the wheels' scale a state, take each leaving point's depth prior (initial_depth,
  // inverse_depth_sigma) back out of the state. Each new point's prior is a guess of the scene's
  // scale, and thousands of them on a long drive outweigh what the mirror shows of it: on the
  // 3,000-frame drive with odometry and gyro the wheels' scale ended at 1.0066 +- 0.0009 for a
  // true 0.9852 with the priors kept, 0.9936 +- 0.0009 without (at an initial depth of 1 m:
  // 0.940), and the pose's NEES over frames 2,400-2,700 went from 464 to 120. Taken back only
  // where the measurements have at least halved the prior's variance, where the linear take-back
  // is well conditioned. Vision alone the priors are all that holds the scale: taken back there,
  // the 600 m drives' error after a similarity alignment rose from 8.1-10.1 % to 9.5-13.0 %.
  bool take_back_depth_priors = true;
  // The camera's calibration uncertainty (the camera file's [omni_camera_covariance], through
  // camera_prior_from): those parameters become consider states (filter_state.h), so that every
  // measurement's and every new point's error from the camera is carried, with its correlations
  // across frames, in the covariance the filter publishes. A calibration error is the same in
  // every frame, which no widening of each measurement's own noise can represent: over rover
  // seeds 1-25 with cameras drawn from a calibration's covariance, the pose's mean NEES is 30
  // with the camera taken as exact, 13-23 with pixel_sigma widened to 0.5-1.2 px, and 5.5 with
  // the covariance considered (eval::rover_pose_consistency; 6 is honest). Empty: the camera is
  // exact.
  CameraPrior camera_uncertainty;
  // Vision alone, after the smoothed start: the frames since the window last closed are solved
  // again exactly (Ceres' Levenberg-Marquardt over their poses and points: their measurements,
  // the new points' depth priors, the random walk, and the filter's estimate where the window
  // opened, pose and points, as a Gaussian prior with its covariance), and the filter restarts
  // from that solution with its covariance, as after the smoothed start. The window closes before
  // the state's origin moves (so that it lives in one frame), or after smoothing_window_frames
  // frames. The filter linearises each measurement once, at its frame's estimate, and at 0.2 px
  // that let the noise grow the map to 3.5 times the truth's over the 600 m drive while the pose's
  // covariance grew overconfident (mean NEES over its last 5,000 frames 149 / 438 / 567 at seeds
  // 1-3; 6 when honest). With the window (closing every 26 frames there, as the origin moves):
  // 23 / 12 / 20, the map 1.2 times the truth's, the mean orientation error 2.28 / 1.08 / 2.08 deg
  // (0.86 / 2.07 / 1.99 without; 1.61 and 1.57 on average over seeds 1-6) and the drive 0.83-1.36 %
  // off after a similarity (0.18-0.38 %: the map's scale settles over the first 10,000 frames).
  // A window costs a solve that grows with the cube of the live points (about 30 ms at 30 on the
  // drive, 0.3 s at 110 on the rover), hence windows as long as the origin allows, and none solved
  // while the state holds more than 60 points (on the rover, with 110, they changed no figure).
  // Off once a frame was propagated by the vehicle's sensors, and with considered camera
  // parameters (the window carries neither's covariance). Not the default: over the 3 km soak the
  // orientation's error reached 22 deg where the filter alone kept it within 7.3 (its NEES 1,077
  // at 2.7 km against 2,365), each frame took 1.4 ms against 0.28, and the resident memory grew
  // 2.6 MB (0.69). 0: off; 60 is what the figures above were measured with.
  int smoothing_window_frames = 0;
  // How many of the latest ended points and rejected tracks points() and rejected() keep; the
  // callbacks (OnlineFilter::on_point_ended, on_track_rejected) are handed every one.
  int kept_history = 10000;
  // The most points the state holds at once: each adds six columns to the covariance, whose
  // update grows with their square (4 ms a frame at 112 points; 3,000 tracks at once took minutes
  // a frame and gigabytes). A new track beyond it waits until a point leaves (not_admitted()
  // counts its frames), and the batch places such tracks by triangulation from the filter's poses.
  int max_live_points = 300;
};

// The camera's motion since the previous frame as the vehicle's sensors predict it:
// cam_from_previous_cam, and the 6x6 covariance of its error (rotation as a left perturbation,
// then translation, as the pose's).
struct MotionPrediction {
  Eigen::Isometry3d cam_from_previous_cam = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
  // With a gyro integrated at the filter's gyro_bias(): the motion's error per unit of the bias's
  // error (true bias = estimate + error), the bias's random walk over the interval (variance per
  // axis), and the bias's prior variance per axis, which the first such prediction sets. All zero
  // without a gyro, or with the bias folded into `covariance` instead.
  Eigen::Matrix<double, 6, 3> bias_jacobian = Eigen::Matrix<double, 6, 3>::Zero();
  double bias_walk_variance = 0;
  double bias_prior_variance = 0;
  // The same for the odometry's distances made at the filter's wheel_scale(): the motion's error
  // per unit of that correction's error, and its prior variance.
  Eigen::Matrix<double, 6, 1> wheel_scale_jacobian = Eigen::Matrix<double, 6, 1>::Zero();
  double wheel_scale_prior_variance = 0;
  // Whether a metric sensor (the odometry) measured the distance moved: from then on the map's
  // scale is the sensor's (OnlineFilter::vision_scale_log_sigma), estimated or not.
  bool measures_distance = false;
};

using core::TrackPixel;

struct RejectedTrack {
  int track = 0;
  // Where the filter rejected it; for the batch's rejections, the first frame beyond its
  // residual limit, or for a track that fails over its length, the frame of its largest residual.
  int frame = 0;
};

// Where a consistency study has the filter take its Jacobians: Huang, Mourikis and Roumeliotis's
// "ideal EKF", linearised at the truth while its estimate still moves by its own residuals. It
// tells an inconsistency of the filter's model from one of its linearisation.
struct LinearisationPoints {
  std::function<Eigen::Isometry3d(int frame)> cam_from_world;
  std::function<Eigen::Vector3d(int track)> world_point;  // in the filter's world, the first frame's
};

class OnlineFilter {
 public:
  OnlineFilter(const camera::CatadioptricCamera& camera, const FilterSettings& settings);

  // Processes the next frame's observations. Returns false when no measurement could be used
  // (the pose then stays the propagated prediction).
  bool process_frame(int frame, const std::vector<TrackPixel>& observations);
  // The same, propagated by the predicted motion instead of the random walk (ignored for the
  // first frame, which fixes the gauge).
  bool process_frame(int frame, const std::vector<TrackPixel>& observations,
                     const MotionPrediction& motion);

  // Called as a point leaves the filter for good, its track ended, with its last estimate (world
  // frame); while the smoothed start is pending, once it has revised them. A point whose track the
  // filter still holds at the end of a sequence is in points() only.
  using PointEnded = std::function<void(int track, const Eigen::Vector3d& point)>;
  void on_point_ended(PointEnded callback) { point_ended_ = std::move(callback); }
  // Called as a track is rejected as an outlier.
  using TrackRejected = std::function<void(const RejectedTrack&)>;
  void on_track_rejected(TrackRejected callback) { track_rejected_ = std::move(callback); }
  // Called with a frame whose predicted motion (process_frame's `motion`) the images refused:
  // under it the established points' median innovation score was beyond any noise's (an
  // odometry that jumps, a gyro's spike, a reading misdated), or beyond a consistent
  // prediction's frame after frame (a sensor that fails for good: a wheel that stops counting, a
  // gyro stuck), and under the filter's own constant-velocity prediction, which the frame then
  // took, within. The sensors' readings over that interval are wrong, and the batch leaves them
  // out. Where the images fit neither, the sensors' motion stands.
  using MotionRefused = std::function<void(int frame)>;
  void on_motion_refused(MotionRefused callback) { motion_refused_ = std::move(callback); }

  // From now on the measurements, a new point's start (the pose its anchor hangs on) and the
  // vehicle's motion are linearised at `points`, once per update (update_iterations is taken as
  // 1): for consistency studies (eval::rover_pose_consistency). Still at the estimate: the
  // smoothed start's solve and covariance (a batch over its window, relinearised to convergence),
  // the motion prediction's Jacobians in the gyro's bias and the wheels' scale (the caller's,
  // from sensor_states()), and a measurement whose given point does not project.
  void linearise_at(LinearisationPoints points) { linearisation_points_ = std::move(points); }

  const camera::CatadioptricCamera& camera() const { return camera_; }
  Eigen::Isometry3d cam_from_world() const { return state_.world_cam_from_world(); }
  // The 6x6 covariance of the pose error (rotation, then translation) in the first frame's gauge.
  // Without odometry it holds the map's scale too (vision_scale_log_sigma()), along the direction
  // a change of scale moves the pose: its translation's.
  Eigen::Matrix<double, 6, 6> pose_covariance() const;
  // Until odometry comes, nothing fixes the map's scale but the depth priors and the mirror's few
  // centimetres, which the online updates weigh wrongly: at 0.2 px the iterated updates grow the
  // map until a frame's step is about two translation_walk_sigma (5.6-6.6x at the rover's end,
  // seeds 1-25; 3.2-3.6x over the 600 m drive, whatever the priors' depth), where the batch, from
  // the same tracks, finds the scale within its sigma. The state's covariance is then conditional
  // on the scale, and pose_covariance() adds the scale's own: the truth is the map scaled by
  // exp(-u), u of this sigma, linearised, so the translation's error along itself has sigma
  // |t|, which holds a map up to 2x small or any larger ((1 - 1/s) |t|). The sigma is the depth
  // prior's relative one, inverse_depth_sigma times initial_depth (1 by default). Over rover seeds
  // 1-25 the maps all grew, and the term holds them linearised (the error along the scale over
  // this sigma: mean square 0.70), not their logarithm (1.8 sigmas). 0 once odometry has measured
  // a distance (MotionPrediction::measures_distance), the wheels' scale estimated or not; the
  // map made before then keeps its scale and the term leaves at once.
  double vision_scale_log_sigma() const;
  // The tracks' noise the filter takes, pixels per coordinate: pixel_sigma, or what it measured
  // where that is well beyond (FilterSettings::measure_noise), at most kMaxNoiseScale times
  // pixel_sigma (a filter that has lost its way sees every track off, and taking that as noise
  // would accept them all).
  double pixel_sigma() const { return settings_.pixel_sigma * noise_scale_; }
  static constexpr double kMaxNoiseScale = 10;
  // The gyro's bias (rad/s about the body's axes), zero until a prediction brings a gyro, and its
  // covariance.
  const Eigen::Vector3d& gyro_bias() const { return state_.mean.sensors.gyro_bias; }
  Eigen::Matrix3d gyro_bias_covariance() const {
    return state_.P.block<3, 3>(FilterState::kBiasColumn, FilterState::kBiasColumn);
  }
  // The correction of the wheels' calibrated scale, 1 until a prediction brings odometry, and its
  // variance.
  double wheel_scale() const { return state_.mean.sensors.wheel_scale; }
  double wheel_scale_variance() const {
    return state_.P(FilterState::kScaleColumn, FilterState::kScaleColumn);
  }
  const SensorStates& sensor_states() const { return state_.mean.sensors; }
  // The latest estimate of the live points and of the ended ones kept (the latest kept_history,
  // and every one while the smoothed start is pending), outliers excluded, and those measured
  // once only (made of the depth prior alone) too, as on_point_ended leaves them out.
  std::map<int, Eigen::Vector3d> points() const;
  // The latest kept_history rejected tracks, oldest first.
  const std::deque<RejectedTrack>& rejected() const { return rejected_; }
  // The poses of the first frames as the smoothed start revised them (frame -> cam_from_world);
  // empty until it has run.
  const std::map<int, Eigen::Isometry3d>& smoothed_start() const { return smoothed_start_; }
  // At a sequence's end: where it was shorter than smoothed_start_frames, the smoothed start over
  // the frames it had (without it the lab's 41 frames, asked for 42, were 1.3 % off where they are
  // 0.03 %); nothing otherwise.
  void finish_start();
  int num_live_points() const { return state_.num_slots(); }
  // Observations of new tracks that waited for room (FilterSettings::max_live_points).
  long not_admitted() const { return not_admitted_; }
  // Frames whose predicted motion the images refused (on_motion_refused).
  long refused_motions() const { return refused_motions_; }
  // Linearisations of the measurements (each a P H^T, S and its factor) over all updates so far,
  // outlier re-runs included: the measure of the iterated update's work.
  long linearisations() const { return linearisations_; }
  // The sliding window's solves taken so far, and those refused (FilterSettings::
  // smoothing_window_frames).
  long window_solves() const { return window_solves_; }
  long window_refusals() const { return window_refusals_; }

 private:
  // A measurement's predicted pixel at some state, and its Jacobians there.
  struct Linearisation {
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 6> pose;   // rotation (left perturbation), then translation
    Eigen::Matrix<double, 2, FilterState::kPointSize> point;  // the point's parameters
    Eigen::Matrix<double, 2, Eigen::Dynamic> camera;  // the considered camera parameters
  };
  struct Measurement {
    int slot;
    Eigen::Vector2d pixel;
    Linearisation at_prior;  // at the propagated state, shared by the outlier test's re-runs
  };
  // Where a frame's update is linearised: at iterates it chooses (the iterated EKF), first at the
  // vehicle's sensors' prediction, or once at the constant velocity
  // (FilterSettings::linearise_at_constant_velocity).
  enum class LinearisedAt { kIterates, kPrediction, kConstantVelocity };
  // An update not yet accepted: the new mean, its residuals, and what the covariance downdate
  // needs, so that an update the outlier test refuses costs no covariance work.
  struct Candidate {
    FilterMean mean;
    std::vector<double> residuals;  // per measurement, after the update: its norm
    Eigen::VectorXd residual;       // the residuals themselves, two rows per measurement
    Eigen::MatrixXd PHt;            // P H^T at the last linearisation
    Eigen::MatrixXd S_factor;       // the innovation covariance's Cholesky factor (lower)
    // With considered camera parameters, H_c (P H^T)_c at the last linearisation: the part of S
    // the update does not take out of the residuals (posterior_chi2).
    Eigen::MatrixXd unestimated;
    int linearisations = 0;         // that the update took
  };
  // An iterate of the update, x_i. Offsets x - x_prior hold the rotation in the prior's chart,
  // R = exp(theta) R_prior, so H's rotation columns are the left perturbation's times the chart's
  // Jacobian. H is sparse: each measurement's two rows touch the pose and its own point only;
  // the pose columns of all rows are kept together, for one product with P's pose columns.
  struct Iterate {
    Eigen::Matrix<double, Eigen::Dynamic, 6> H_pose;
    std::vector<Eigen::Matrix<double, 2, FilterState::kPointSize>> H_point;
    Eigen::MatrixXd H_camera;  // the considered camera parameters' columns, two rows each
    // Per measurement, from the last iterate where it projected: h(x_i), z - h(x_i) (infinite
    // where it did not project here), H_i (x_i - x_prior) and the innovation
    // z - h(x_i) + H_i (x_i - x_prior).
    Eigen::VectorXd pixels, residual, H_offset, innovation;
    Eigen::VectorXd offset;  // x_i - x_prior = P g
    Eigen::VectorXd g;
    double cost = 0;         // the posterior cost at x_i (infinite where a point did not project)

    void allocate(int measurements, int camera_params);  // the per-measurement parts

    // Measurement k linearised at this iterate (its offset set), `observed` its pixel and its
    // point's parameters at `point_column` of the state: h(x_i) and z - h(x_i), and with
    // `jacobians` also H's rows (the rotation's times `chart`), H_i (x_i - x_prior) and the
    // innovation. Returns |z - h(x_i)|^2.
    double take(int k, const Linearisation& lin, const Eigen::Vector2d& observed,
                int point_column, const Eigen::Matrix3d& chart, bool jacobians);
  };
  // Both process_frame overloads: propagated by `motion` when given, else by the random walk.
  bool process(int frame, const std::vector<TrackPixel>& observations,
               const MotionPrediction* motion);
  // The observations of tracks not rejected, by track; rejected tracks no longer observed are
  // forgotten.
  std::map<int, Eigen::Vector2d> usable(const std::vector<TrackPixel>& observations);
  // The measurements of the tracks the state holds, linearised at the propagated state (at the
  // given points in a consistency study), those that project there.
  std::vector<Measurement> measurements_of(const std::map<int, Eigen::Vector2d>& seen) const;
  // The innovation gate, then the update with the outlier test: the worst track dropped and the
  // update redone until every residual passes. The dropped tracks' slots go to rejected_slots.
  // False when no measurement is left to update with.
  bool update_rejecting_outliers(std::vector<Measurement> measurements, LinearisedAt linearised_at,
                                 std::set<int>* rejected_slots);
  void propagate();
  void propagate(const MotionPrediction& motion);
  // What propagate(motion) changes, to try another prediction instead: the mean, the pose's rows
  // of the covariance (its columns are their transpose) and the gyro bias's block.
  struct BeforePropagation {
    FilterMean mean;
    Eigen::MatrixXd pose_rows;
    Eigen::Matrix3d bias_block;
  };
  BeforePropagation before_propagation() const;
  void restore(const BeforePropagation& before);
  // Propagated by `motion`, the frame's measurements at the propagated state; where the images
  // refuse it (on_motion_refused), by the constant-velocity prediction instead (a single frame's
  // gross misfit) or the random walk (a fault that lasts; with the gyro's rotation where only the
  // wheels are at odds), which `motion` then points to. A prediction that leaves part of the
  // rotation to the walk (odometry without a gyro) is judged after a trial update too, and one
  // that leaves the translation to it (a gyro alone) after a trial update only.
  std::vector<Measurement> propagate_checked(const std::map<int, Eigen::Vector2d>& seen,
                                             const MotionPrediction** motion);
  // The established points' median innovation score (chi-square, 2 dof) under a prediction:
  // beyond the outlier bound (FilterSettings::outlier_chi2) most good tracks would be rejected,
  // and the prediction is in gross error. NaN (not judged) with fewer than
  // kMinPointsToJudgeMotion of them (online_filter.cpp).
  double motion_misfit(const std::map<int, Eigen::Vector2d>& seen,
                       const std::vector<Measurement>& measurements) const;
  // The established points' scores' `quantile` (chi-square, 2 dof) after an update by
  // `measurements`, NaN as motion_misfit's; and whether their median lies within the outlier
  // bound: the images agree on one pose.
  double misfit_after_update(const std::vector<Measurement>& measurements, double quantile) const;
  bool fits_after_update(const std::vector<Measurement>& measurements) const;
  // The motion between the last two frames as the filter estimated them, with the random walk's
  // covariance.
  MotionPrediction constant_velocity() const;
  // After a frame the vehicle's sensors predicted: the rotation and the distance they measured,
  // each against the frame's motion the filter estimated, summed as sensor_misfit_sum_ is, so
  // that once one sensor's lasting fault refuses the sensors' motion, the other's part may stay.
  void judge_motion_parts(const MotionPrediction& given);
  // `walk` with the rotation of the refused `given` (the gyro's), and its error's dependence on
  // the gyro's bias.
  static MotionPrediction with_rotation_of(const MotionPrediction& given, MotionPrediction walk);
  // Counts the frame's predicted motion as refused and says so (on_motion_refused).
  void refuse_motion_at(int frame);
  // No motion, with the random walk's covariance (FilterSettings::rotation_walk_sigma,
  // translation_walk_sigma).
  MotionPrediction random_walk() const;
  // The frame's estimated pose and motion since the previous, for constant_velocity().
  void note_pose();
  // A track's point leaves the state: held while the smoothed start is pending, else handed over.
  void end_point(int slot);
  // The ended point to the callback and into the kept history.
  void hand_over(int track, const Eigen::Vector3d& point);
  // An outlier: out of the state and the results for good, listed in rejected().
  void reject(int track, int frame);
  // Moves the update's first iterate from the prediction to the posterior's minimum along the
  // pose's direction of the prior (see online_filter_pose_start.cpp); point_columns[k] is where
  // measurement k's point sits in the state. False, leaving it, with too few points, when a point
  // does not project there, or when it does not lower the cost.
  bool start_on_pose_subspace(const std::vector<Measurement>& measurements,
                              const std::vector<int>& point_columns, Iterate* prior) const;
  // The squared Mahalanobis distance of a measurement's innovation at the propagated state.
  double prior_chi2(const Measurement& measurement) const;
  // The update's first iterate, at the propagated state or where the iterations start from it
  // (online_filter.cpp); `warm_step`: a linearisation point only, not yet an update.
  Iterate first_iterate(const std::vector<Measurement>& meas, const std::vector<int>& point_columns,
                        bool predicted, int linearisations, bool* warm_step) const;
  // The measurements at an iterate's mean `moved` (`next`'s offset set): its pixels, residuals and
  // cost (added to next->cost, infinite where a point does not project), with `jacobians` its
  // Jacobians too; whether every pixel moved by less than `settled_px` from `at`'s, and the
  // largest miss of `at`'s linear model.
  struct IterateCheck {
    bool settled = true, projected = true;
    double linearisation_error = 0;
  };
  IterateCheck project_iterate(const std::vector<Measurement>& meas,
                               const std::vector<int>& point_columns, const FilterMean& moved,
                               bool jacobians, bool warm_step, double settled_px,
                               const Iterate& at, Iterate* next) const;
  // P H^T and H P H^T (S's lower triangle, without the noise) from the blocks of `at`'s H.
  void project_covariance(const Iterate& at, const std::vector<int>& point_columns,
                          Eigen::MatrixXd* PHt, Eigen::MatrixXd* S) const;
  // The step from `at` with Levenberg's damping mu, S_factor the (damped) innovation
  // covariance's Cholesky factor: next's offset from the prior and its g. Returns the posterior
  // cost the linear model predicts there.
  double take_step(const Iterate& at, const std::vector<int>& point_columns,
                   const Eigen::MatrixXd& PHt, const Eigen::MatrixXd& S_factor, double mu,
                   Iterate* next) const;
  // The update from the current (propagated) state, linearised where `linearised_at` says.
  void update(const std::vector<Measurement>& measurements, LinearisedAt linearised_at,
              Candidate* candidate) const;
  void accept(Candidate* candidate);
  void add_point(int track, const Eigen::Vector2d& pixel);
  // How a new point's parameters about `anchor`, started from a pixel whose ray moves by `ray`
  // (unprojection's Jacobian) seen from the pose's rotation R, move with the considered camera
  // parameters' errors (FilterState::add's G_camera).
  Eigen::MatrixXd ray_camera_jacobian(const PointAnchor& anchor, const camera::RayJacobian& ray,
                                      const Eigen::Matrix3d& R) const;

  static constexpr double kChiSquare2Median = 1.3862943611198906;  // 2 ln 2
  // One kilometre: far enough to stand for infinity in any scene the rig maps.
  static constexpr double kMinInverseDepth = 1e-3;

  // The pixel of the point (anchor, params) from the pose (R, t), with its Jacobians when asked.
  // False where the point does not project.
  bool linearise(const PointAnchor& anchor, const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                 const PointParams& params, bool jacobians, Linearisation* out) const;

  // What the smoothed start needs of the frames so far: per frame, the pose's estimate, the
  // motion prior into it (none for the first) with the sensors' states it was predicted at, and
  // the observations of tracks in the state; per track, its anchor.
  struct StartFrame {
    int frame = 0;
    Eigen::Matrix3d R;
    Eigen::Vector3d t;
    bool random_walk = true;  // else `motion`
    MotionPrediction motion;
    SensorStates predicted_at;
    std::vector<TrackPixel> observations;
  };
  void record_start_frame(int frame, const std::vector<TrackPixel>& observations,
                          const MotionPrediction* motion, const SensorStates& predicted_at);
  // The start solved (online_filter_smoothed_start.cpp), then the points it held handed over.
  void smooth_start();
  void solve_start();
  struct StartEstimate;
  struct StartWindow;
  // The window's problem from the frames recorded, and in `x` its start, the filter's estimates.
  StartWindow start_window(StartEstimate* x);
  // Solved with the paper's rejection, `A` the normal equations at the solution; false where the
  // filter's own estimate does not project.
  bool solve_start_window(StartWindow* window, StartEstimate* x, Eigen::MatrixXd* A);
  // The filter restarted from the solution: its last pose, the sensors and the live points, with
  // their covariance from A's inverse, and the window's poses and held points revised.
  void restart_from(const StartWindow& window, const StartEstimate& x, const Eigen::MatrixXd& A);

  // The sliding window (FilterSettings::smoothing_window_frames; online_filter_window.cpp), in
  // the state's frame (it closes before the frame moves): the filter's estimate where it opened
  // (its prior) and, per frame since, the pose and the observations of the tracks in the state;
  // per point started since, its anchor and the window's pose it hangs on; every point's latest
  // parameters.
  struct WindowFrame {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    std::vector<TrackPixel> observations;
  };
  struct WindowPrior {
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    std::map<int, int> place;  // track -> its point's place (0, 1, ...)
    std::vector<PointAnchor> anchors;
    std::vector<PointParams> params;
    Eigen::MatrixXd covariance;   // the pose's six, then six per point
    Eigen::MatrixXd with_origin;  // their covariance with the state frame's place
  };
  struct WindowStart {
    PointAnchor anchor;
    int pose = 0;  // the window's pose it was started from (1: the first frame after the prior)
  };
  struct WindowSolution;
  bool window_on() const;
  void open_window();
  // The frame's pixels of `tracks` (those measured, and the new points' first).
  void record_window_frame(const std::map<int, Eigen::Vector2d>& seen,
                           const std::set<int>& tracks);
  // Solves the window and restarts the filter from its solution; where it did not solve or left a
  // pixel beyond the residual limit, changes nothing (counted in window_refusals()).
  void close_window();
  bool solve_window(WindowSolution* solution) const;
  void restart_from_window(const WindowSolution& solution);
  void forget_window_track(int track);
  // A track the window saw is started again after a gap: its sightings so far, the earlier
  // point's, go under a key of their own (negative), as a point that ended.
  void retire_window_track(int track);
  bool window_open_ = false;
  bool predicted_ = false;  // a frame was propagated by the vehicle's sensors
  int next_retired_key_ = -1;
  WindowPrior window_prior_;
  std::vector<WindowFrame> window_frames_;
  std::map<int, WindowStart> window_starts_;
  std::map<int, PointParams> window_latest_;
  long window_solves_ = 0, window_refusals_ = 0;

  bool at_given_points() const { return static_cast<bool>(linearisation_points_.cam_from_world); }

  // Whether the camera is far enough from the state's origin to move it there (see
  // FilterSettings::origin_follows_camera).
  bool camera_far_from_origin() const;

  camera::CatadioptricCamera camera_;  // as given: the pixels that start points
  // The same with the mirror's patch a little wider, for predicted pixels: a track seen just
  // inside the rim is as often predicted just outside it, and was rejected for it, or froze the
  // smoothed start's solve (CatadioptricCamera::with_wider_patch).
  camera::CatadioptricCamera prediction_camera_;
  FilterSettings settings_;
  // The established points' recent outlier scores (a ring), and the factor on pixel_sigma they
  // call for (FilterSettings::measure_noise).
  std::vector<double> recent_scores_;
  std::size_t recent_next_ = 0;
  double noise_scale_ = 1;
  void measure_noise(const std::vector<double>& established_scores);
  // Takes the noise whose variance is `implied_scale2` times the stated one, or lets it go.
  void take_noise(double implied_scale2);
  // The recent established points' scores' median over chi-square's, at the noise taken: about
  // the tracks' noise variance over the one the filter scores at (1 before enough are measured).
  double noise_ratio() const;
  // How far a pixel may be from a solution that explains it, at the noise the filter takes.
  double residual_limit_px() const;
  LinearisationPoints linearisation_points_;
  int frame_ = 0;           // the frame being processed
  int previous_frame_ = 0;  // and the one before
  long not_admitted_ = 0;
  long refused_motions_ = 0;
  // The sensors' predictions' summed excess misfit (propagate_checked), the frames that took
  // their motion since it last rose from 0, and the median misfit a consistent prediction stays
  // below (chi-square's, 2 dof, is 1.39).
  double sensor_misfit_sum_ = 0;
  std::deque<int> suspect_frames_;
  static constexpr double kConsistentMisfit = 2;
  // For the upper quartile of the scores after a trial update (propagate_checked): chi-square's
  // (2 dof) 1 - 1e-3 quantile, and its upper quartile (2.77) with the margin kConsistentMisfit
  // leaves over its median (1.39), at the tracks' noise (noise_ratio()).
  static constexpr double kGrossAfterUpdate = 13.82;
  static constexpr double kConsistentAfterUpdate = 4;
  // The last two frames' estimated poses in the world (constant_velocity()).
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_motion_ = Eigen::Isometry3d::Identity();
  // FilterSettings::linearise_at_constant_velocity: the last updated frame's motion, where a frame
  // the random walk propagated is linearised (none before the first update).
  std::optional<Eigen::Isometry3d> walk_linearisation_motion_;
  MotionPrediction fallback_motion_;  // the refused frame's prediction
  int refused_in_a_row_ = 0;          // frames up to the last whose sensors were refused
  // The distance the wheels measured at the last frame they were taken unsuspected, metres.
  double consistent_step_m_ = 0;
  // The rotation's and the distance's summed excess misfit against the filter's estimate
  // (judge_motion_parts): the squared error over its variance, which takes both the sensor's and
  // the estimate's, in excess of its degrees of freedom (an honest error's mean score).
  double rotation_misfit_sum_ = 0;
  double distance_misfit_sum_ = 0;
  bool started_ = false;
  FilterState state_;
  bool bias_started_ = false;   // its prior set by the first prediction with a gyro
  bool scale_started_ = false;  // by the first with odometry, the wheels' scale a state
  bool distance_measured_ = false;  // by the first with odometry
  // Ended points: held for the smoothed start while it is pending; then the latest kept_history
  // handed over, a ring (no allocation once full, however long the run) whose oldest is at
  // history_next_.
  std::map<int, Eigen::Vector3d> held_points_;
  struct EndedPoint {
    int track;
    bool rejected;  // later, after its track came back
    Eigen::Vector3d point;
  };
  std::vector<EndedPoint> history_;
  std::size_t history_next_ = 0;
  // Rejected tracks, ignored while they are still observed (and throughout the smoothed start's
  // window, which it solves again).
  std::set<int> excluded_;
  std::deque<RejectedTrack> rejected_;
  PointEnded point_ended_;
  TrackRejected track_rejected_;
  MotionRefused motion_refused_;
  long linearisations_ = 0;
  bool smoothing_start_ = false;           // until the smoothed start has run
  std::vector<StartFrame> start_frames_;

  std::map<int, PointAnchor> start_anchors_;
  std::map<int, Eigen::Isometry3d> smoothed_start_;
};

}  // namespace omnisfm::sfm
