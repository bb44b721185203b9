#include "omnisfm/mrpt_plugin/omni_sfm_batch_estimator.h"

#include <stdexcept>

#include "eigen_poses.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/sfm/fused_pipeline.h"

namespace omnisfm::mrpt_plugin {

OmniSfmBatchEstimator::OmniSfmBatchEstimator(const OmniSfmEstimatorOptions& options,
                                             const sfm::BatchSettings& batch)
    : options_(options), batch_(batch) {
  // Said here rather than as the estimate's input's fault.
  if (const std::string problem = options_.problem(); !problem.empty())
    throw std::invalid_argument(problem);
}

namespace {

ReplayOptions replay_options(const OmniSfmEstimatorOptions& o) {
  ReplayOptions r = o.run_options().replay;
  r.camera = o.camera;
  return r;
}

}  // namespace

OmniSfmBatchResult OmniSfmBatchEstimator::estimate(const std::string& rawlog_path) const {
  return estimate(read_replay_input(rawlog_path, replay_options(options_)), rawlog_path);
}

OmniSfmBatchResult OmniSfmBatchEstimator::estimate(const mrpt::maps::CSimpleMap& map) const {
  return estimate(read_replay_input(map, replay_options(options_)), "the simple map");
}

OmniSfmBatchResult OmniSfmBatchEstimator::estimate(ReplayInput in,
                                                   const std::string& source) const {
  if (!in.camera)
    throw io::InputError(source, 0, "carries no camera model: give the options' camera");
  if (in.frame_times.size() < 2)
    throw io::InputError(source, 0,
                         "holds " + std::to_string(in.frame_times.size()) +
                             " camera frames: nothing to estimate from");
  options_.set_sensor_noises(&in.sensors);
  sfm::SfmSettings settings;
  settings.filter = options_.filter;
  settings.batch = batch_;
  settings.run_batch = true;
  settings.leave_out_unplaceable_gps = true;  // estimate.gps_left_out says why

  OmniSfmBatchResult out;
  out.problem = in.read.problem;
  try {
    out.estimate = sfm::run_fused_sfm(*in.camera, in.tracks, in.frame_times, in.sensors, settings);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(source, 0, e.what());
  }
  const sfm::BatchResult& batch = out.estimate.batch;
  if (!batch.usable()) throw std::runtime_error("the batch adjustment failed: " + batch.message);

  out.map_is_enu = out.estimate.world_is_enu;
  const Eigen::Isometry3d& body_from_cam = in.sensors.body_from_cam;
  const Eigen::Isometry3d map_from_world =
      out.map_is_enu ? Eigen::Isometry3d::Identity()
                     : Eigen::Isometry3d(body_from_cam * batch.world_from_cam.front().inverse());
  const bool uncertain = batch.cam_from_world_covariances.size() == batch.world_from_cam.size() &&
                         batch.cam_from_world_parameters.size() == batch.world_from_cam.size();
  for (size_t f = 0; f < batch.world_from_cam.size(); ++f) {
    out.timestamps.push_back(mrpt::Clock::fromDouble(in.frame_times[f]));
    mrpt::poses::CPose3DPDFGaussian pdf;
    pdf.mean = pose_of(map_from_world * batch.world_from_cam[f] * body_from_cam.inverse());
    if (uncertain) {
      // The parameters are cam_from_world, as the covariance's coordinates.
      const auto robot_pose = [&](const core::PoseVector& parameters) {
        return pose_of(map_from_world * core::isometry_of(parameters).inverse() *
                       body_from_cam.inverse());
      };
      const Eigen::Matrix<double, 6, 6> J =
          mrpt_parameters_jacobian<6>(robot_pose, batch.cam_from_world_parameters[f]);
      const Eigen::Matrix<double, 6, 6> covariance =
          J * batch.cam_from_world_covariances[f] * J.transpose();
      pdf.cov = mrpt::math::CMatrixDouble66(
          Eigen::Matrix<double, 6, 6>(0.5 * (covariance + covariance.transpose())));
    } else {
      pdf.cov.setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    out.robot_poses.push_back(pdf);
  }
  for (const auto& [track, point] : batch.points) {
    const Eigen::Vector3d p = map_from_world * point;
    out.points.insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()),
                           static_cast<float>(p.z()));
  }
  return out;
}

}  // namespace omnisfm::mrpt_plugin
