#pragma once
// omnisfm's online estimator as one of MRPT's SLAM front ends: an mrpt::slam::CMetricMapBuilder,
// so that an MRPT application holds it as a CMetricMapBuilder*, feeds it what a rawlog or a live
// sensor loop delivers and reads the robot's pose with its covariance, the keyframes and the map.
//
// It wraps the tracker (libs/track) and the online filter (sfm::OnlineFilter): an omnisfm
// CObservationTrackedFeatures goes to the filter directly; an image (CObservationOmniImage, or a
// stock CObservationImage after a CObservationCameraModel of its label, or when the options give
// the camera) goes through the tracker first. The first kind to arrive is the vision and the other
// is ignored, so that a rawlog holding both a camera's images and their tracks (`omnisfm simulate
// --render --rawlog`) gives each frame once.
// Odometry, gyro and GPS observations and CActionRobotMovement2D actions are collected as
// sfm::MotionSensors (motion_sensor_collector.h) for the estimators that fuse them.
//
// Frames: the map frame is the robot's frame at the first camera frame (x forward, y left, z up,
// MRPT's convention), so the pose starts at the origin. The robot's pose is
//   map_from_robot = body_from_cam * cam0_from_cam * cam_from_body,
// body_from_cam the camera's pose on the robot from the first camera observation. Its covariance
// is the filter's pose covariance carried through that map to MRPT's (x, y, z, yaw, pitch, roll)
// to first order, with the Jacobian by central differences.
//
// The map (CMetricMapBuilder's terms): keyframes, a camera observation with the robot's pose PDF
// at that moment, taken once the robot has moved keyframe_distance_m or turned keyframe_angle_rad
// since the last one (as MRPT's ICP builder inserts by distance), while map updating is enabled;
// and the metric map, the filter's points (points()) as a CSimplePointsMap. Keyframes grow with
// the distance driven; disable map updating (enableMapUpdating(false)) for a run that must not.
//
// MRPT headers: the including target must link MRPT (mrpt::obs, mrpt::poses, mrpt::maps,
// mrpt::slam) itself.

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMultiMetricMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/slam/CMetricMapBuilder.h>

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/mrpt_plugin/image_camera_models.h"
#include "omnisfm/mrpt_plugin/motion_sensor_collector.h"
#include "omnisfm/mrpt_plugin/run_options.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/track/tracker_settings.h"

namespace omnisfm::track {
class SequenceTracker;
}

namespace omnisfm::mrpt_plugin {

// Loadable from an INI file as MRPT's builders' options are (loadFromConfigFile): the section
// given holds the keys of `omnisfm run`'s [run] section (run_options.h), and a section [sfm], when
// the file has one, the online filter's keys of `omnisfm sfm`'s [sfm] (sfm/settings_file.h; its
// batch keys are read and not used). The shipped share/omnisfm/config/omnisfm.ini loads with
// section "run". A key of neither, or a bad value, is an io::InputError naming the file and key.
struct OmniSfmEstimatorOptions : public mrpt::config::CLoadableOptions {
  sfm::FilterSettings filter;
  track::TrackerSettings tracker;
  // The camera; without one, the model the first omnisfm observation carries.
  std::optional<camera::CatadioptricCamera> camera;
  std::string camera_label;  // the camera's (or its tracks') sensor label; empty: any
  // OmniSfmBatchEstimator's choice of vision ([run] vision); OmniSfmEstimator takes the first
  // kind of camera observation to arrive.
  ReplayVision vision = ReplayVision::kAuto;
  MotionSensorLabels sensor_labels;
  std::optional<GeodeticPoint> gps_origin;
  // The dead reckoning's noise models, and the wheels' scale (true distance per distance read,
  // as a run with GPS estimates it: sfm::SfmResult::odometry_scale).
  sfm::OdometryNoise odometry_noise;
  sfm::GyroNoise gyro_noise;
  double odometry_scale = 1;
  // A keyframe once the robot has moved this far, or turned this much, since the last one.
  double keyframe_distance_m = 1.0;
  double keyframe_angle_rad = 10 * M_PI / 180;

  // The same options in the replay's terms, and back (the filter and the camera apart).
  RunOptions run_options() const;
  void set_run_options(const RunOptions& run);
  // "" when the filter's settings and the sensors' noises are within what they can mean
  // (sfm/settings_ranges.h, sfm/sensor_ranges.h), else the first that is not, named; the
  // estimators' constructors throw std::invalid_argument with it.
  std::string problem() const;
  // Sets `sensors`' noises and wheel scale to these options' (their readings stay).
  void set_sensor_noises(sfm::MotionSensors* sensors) const;

  void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                          const std::string& section) override;
  // Writes the section's keys (not [sfm]'s).
  void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                        const std::string& section) const override;
};

class OmniSfmEstimator : public mrpt::slam::CMetricMapBuilder {
 public:
  explicit OmniSfmEstimator(const OmniSfmEstimatorOptions& estimator_options = {});
  ~OmniSfmEstimator() override;
  OmniSfmEstimator(const OmniSfmEstimator&) = delete;
  OmniSfmEstimator& operator=(const OmniSfmEstimator&) = delete;

  // Starts again, with no frame seen. x0, when given, is where the robot starts in the map (its
  // mean; the filter's own uncertainty starts at zero there). Throws std::invalid_argument for a
  // non-empty initial map: the estimator builds its own.
  void initialize(const mrpt::maps::CSimpleMap& initialMap = mrpt::maps::CSimpleMap(),
                  const mrpt::poses::CPosePDF* x0 = nullptr) override;
  // A sensory-frame rawlog's step: the actions (odometry) first, then the observations.
  void processActionObservation(mrpt::obs::CActionCollection& action,
                                mrpt::obs::CSensoryFrame& observations) override;
  // One observation, as an observation-format rawlog or a live sensor gives it. Throws
  // std::invalid_argument, changing nothing, for an image or tracks when no camera is known (a
  // stock CObservationImage without options.camera), a camera frame at or before the previous
  // one's time, or one whose camera pose on the robot is not the first frame's.
  void processObservation(const mrpt::obs::CObservation::Ptr& observation);

  // The robot's pose in the map frame with its covariance: a CPose3DPDFGaussian, whose
  // covariance is over x, y, z, yaw, pitch, roll; the start (the origin, or initialize's x0),
  // exactly, before the first frame.
  mrpt::poses::CPose3DPDF::Ptr getCurrentPoseEstimation() const override;
  void getCurrentPoseEstimation(mrpt::poses::CPose3DPDFGaussian& out) const;

  // The keyframes, each with its CPose3DPDFGaussian and a sensory frame holding its camera
  // observation.
  void getCurrentlyBuiltMap(mrpt::maps::CSimpleMap& out) const override;
  unsigned int getCurrentlyBuiltMapSize() override;
  // A CMultiMetricMap holding one CSimplePointsMap: points() at the time of the call. MRPT's
  // point maps have no place for each point's covariance; the filter has them.
  const mrpt::maps::CMultiMetricMap* getCurrentlyBuiltMetricMap() const override;
  // A top view (x right, y up) of the keyframes' path, the robot and the points, as an image in
  // the format the file's extension names (CImage::saveToFile). formatEMF_BMP is ignored: MRPT
  // writes EMF on Windows only. Throws std::runtime_error naming the file when it cannot be saved.
  void saveCurrentEstimationToImage(const std::string& file, bool formatEMF_BMP = true) override;

  int framesProcessed() const { return frames_; }
  // The last camera frame's time, seconds since the Unix epoch (0 before any).
  double lastFrameTime() const { return frames_ > 0 ? previous_frame_time_ : 0; }
  // What leaves the filter as it goes (sfm::OnlineFilter::on_point_ended, on_track_rejected):
  // points in the estimator's world, the first camera's frame. Set before the first frame.
  void onPointEnded(sfm::OnlineFilter::PointEnded callback) { point_ended_ = std::move(callback); }
  void onTrackRejected(sfm::OnlineFilter::TrackRejected callback) {
    track_rejected_ = std::move(callback);
  }
  // The filter in the camera's terms (cam_from_world, the world the first camera's frame), once
  // the first camera frame has started it; null before.
  const sfm::OnlineFilter* filter() const { return filter_.get(); }
  // At a sequence's end (a replay's last object): a sequence shorter than the filter's
  // smoothed_start_frames gets its smoothed start over the frames it had
  // (sfm::OnlineFilter::finish_start). The estimator may go on after it.
  void finishStart() {
    if (filter_) filter_->finish_start();
  }
  // The robot's poses (map frame) at the first frames, numbered as framesProcessed() counts them,
  // as the smoothed start revised them after getCurrentPoseEstimation() had given them; empty
  // until it has run.
  std::map<int, mrpt::poses::CPose3D> smoothedStartPoses() const;
  // The points of the live tracks and of the latest ended ones the filter keeps
  // (FilterSettings::kept_history), in the map frame; onPointEnded gets every one as it ends.
  std::map<int, Eigen::Vector3d> points() const;
  // The dead reckoning and GPS readings still held: from the last frame's on (older ones are
  // dropped once used, so memory stays bounded on an endless run).
  const sfm::MotionSensors& motionSensors() const { return collector_.sensors(); }
  // The estimator's world (the first camera's frame) in the map frame.
  Eigen::Isometry3d mapFromWorld() const { return map_from_start_ * body_from_cam_; }

 private:
  void start(const camera::CatadioptricCamera& camera, const mrpt::poses::CPose3D& camera_pose);
  // Refuses a frame at or before the previous one's time, or whose camera pose on the robot is not
  // the one the estimator started with.
  void require_next_frame(const mrpt::poses::CPose3D& pose, double timestamp) const;
  // The filter propagated by the odometry and gyro collected since the previous frame (when there
  // are any), then updated by the frame's pixels.
  void process_frame(const std::vector<sfm::TrackPixel>& pixels, double timestamp,
                     const mrpt::obs::CObservation::Ptr& observation);
  bool is_camera(const mrpt::obs::CObservation& observation) const;
  // The frame's observation as a keyframe when the robot has gone far enough from the last.
  void maybe_add_keyframe(const mrpt::obs::CObservation::Ptr& observation);

  OmniSfmEstimatorOptions options_;
  MotionSensorCollector collector_;
  std::unique_ptr<sfm::OnlineFilter> filter_;
  sfm::OnlineFilter::PointEnded point_ended_;
  sfm::OnlineFilter::TrackRejected track_rejected_;
  std::unique_ptr<track::SequenceTracker> tracker_;
  ImageCameraModels image_models_;
  Eigen::Isometry3d body_from_cam_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d map_from_start_ = Eigen::Isometry3d::Identity();  // initialize's x0
  mrpt::maps::CSimpleMap keyframes_;
  mrpt::poses::CPose3D last_keyframe_pose_;
  mutable mrpt::maps::CMultiMetricMap metric_map_;
  int frames_ = 0;
  double previous_frame_time_ = 0;
};

// MRPT's pose (x, y, z, yaw, pitch, roll) of map_from_robot, and its covariance, from the
// filter's cam_from_world and its 6x6 covariance (rotation error as a left perturbation, then
// translation), with the robot at body_from_cam of the camera and the world the map moved by
// map_from_world.
mrpt::poses::CPose3DPDFGaussian robot_pose_of(const Eigen::Isometry3d& cam_from_world,
                                              const Eigen::Matrix<double, 6, 6>& covariance,
                                              const Eigen::Isometry3d& body_from_cam,
                                              const Eigen::Isometry3d& map_from_world);

}  // namespace omnisfm::mrpt_plugin
