#include "omnisfm/sfm/fused_pipeline.h"

#include <ceres/normal_prior.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "omnisfm/core/mahalanobis.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/core/pose_direction.h"
#include "omnisfm/sfm/frame_motion.h"
#include "omnisfm/sfm/motion_prediction.h"
#include "omnisfm/sfm/motion_residuals.h"
#include "omnisfm/sfm/sensor_ranges.h"
#include "pipeline_steps.h"
#include "so3.h"

namespace omnisfm::sfm {
namespace {

// A GPS fix placed between two frames: alpha of the way from frame k to frame k + 1; `index` is
// its place in MotionSensors::gps.
struct FixPlacement {
  const GpsSample* fix;
  int index;
  int k;
  double alpha;
};

// The fixes within the frames' time span, but those in `refused` (indices into gps).
std::vector<FixPlacement> place_fixes(const std::vector<GpsSample>& gps,
                                      const std::vector<double>& times,
                                      const std::vector<int>& refused = {}) {
  std::vector<FixPlacement> placed;
  for (size_t i = 0; i < gps.size(); ++i) {
    const GpsSample& fix = gps[i];
    if (fix.timestamp < times.front() || fix.timestamp > times.back()) continue;
    if (std::find(refused.begin(), refused.end(), static_cast<int>(i)) != refused.end()) continue;
    const auto after = std::upper_bound(times.begin(), times.end(), fix.timestamp);
    const int k = std::min(static_cast<int>(after - times.begin()) - 1,
                           static_cast<int>(times.size()) - 2);
    placed.push_back(
        {&fix, static_cast<int>(i), k, (fix.timestamp - times[k]) / (times[k + 1] - times[k])});
  }
  return placed;
}

// A fix's noise: horizontal, horizontal, vertical.
Eigen::Matrix3d fix_covariance(const GpsSample& fix) {
  return Eigen::Vector3d(std::pow(fix.horizontal_sigma, 2), std::pow(fix.horizontal_sigma, 2),
                         std::pow(fix.vertical_sigma, 2))
      .asDiagonal();
}

Eigen::Vector3d antenna_in_cam(const MotionSensors& sensors) {
  return sensors.body_from_cam.inverse() * sensors.antenna_in_body;
}

// The antenna's world position at a placed fix, interpolated linearly between the frames around
// it (as the batch's GPS terms do).
Eigen::Vector3d antenna_at(const std::vector<Eigen::Isometry3d>& cam_from_world,
                           const FixPlacement& placed, const Eigen::Vector3d& antenna) {
  const auto position = [&](int k) {
    const Eigen::Isometry3d& T = cam_from_world[k];
    return Eigen::Vector3d(T.linear().transpose() * (antenna - T.translation()));
  };
  return (1 - placed.alpha) * position(placed.k) + placed.alpha * position(placed.k + 1);
}

// The residuals of the vehicle's sensors for the batch; its own blocks are the odometry's scale
// and the gyro's bias, which it re-integrates the gyro about each time it enters a problem.
class MotionTerms : public ExtraTerms {
 public:
  // `refused_frames`: those whose interval from the previous frame the images showed the
  // odometry and gyro mispredicted (SfmResult::refused_motion_frames), left out.
  // `refused_fixes`: the GPS fixes at odds with the rest (SfmResult::refused_gps_fixes), left
  // out.
  MotionTerms(const MotionSensors& sensors, const std::vector<double>& times,
              const Eigen::Vector3d& gyro_bias, const std::set<int>& refused_frames,
              const std::vector<int>& refused_fixes)
      : sensors_(sensors),
        times_(times),
        refused_(refused_frames),
        refused_fixes_(refused_fixes),
        scale_(sensors.odometry_scale),
        bias_(gyro_bias) {}

  bool add(ceres::Problem* problem, std::vector<PoseVector>* poses) override {
    scale_sigma_ = NAN;
    bias_sigma_.setConstant(NAN);
    const std::vector<FrameMotion> motions = frame_motions(sensors_, times_, bias_);
    bool odometry = false, gyro = false;
    for (size_t k = 0; k < motions.size(); ++k) {
      if (refused_.count(static_cast<int>(k) + 1)) continue;
      double* from = (*poses)[k].data();
      double* to = (*poses)[k + 1].data();
      if (motions[k].odometry.valid) {
        problem->AddResidualBlock(make_odometry_cost(motions[k].odometry, sensors_.body_from_cam),
                                  nullptr, from, to, &scale_);
        odometry = true;
      }
      if (motions[k].gyro.valid) {
        problem->AddResidualBlock(make_gyro_cost(motions[k].gyro, sensors_.body_from_cam), nullptr,
                                  from, to, bias_.data());
        gyro = true;
      }
    }
    if (odometry) {
      const double sigma = sensors_.odometry_noise.scale_sigma * sensors_.odometry_scale;
      if (sigma > 0)
        problem->AddResidualBlock(
            new ceres::NormalPrior(ceres::Matrix::Constant(1, 1, 1 / sigma),
                                   ceres::Vector::Constant(1, sensors_.odometry_scale)),
            nullptr, &scale_);
      else
        problem->SetParameterBlockConstant(&scale_);
    }
    if (gyro) {
      const double sigma = sensors_.gyro_noise.bias_sigma;
      if (sigma > 0)
        problem->AddResidualBlock(
            new ceres::NormalPrior(ceres::Matrix::Identity(3, 3) / sigma, ceres::Vector::Zero(3)),
            nullptr, bias_.data());
      else
        problem->SetParameterBlockConstant(bias_.data());
    }
    const Eigen::Vector3d antenna = antenna_in_cam(sensors_);
    int fixes = 0;
    for (const auto& p : place_fixes(sensors_.gps, times_, refused_fixes_)) {
      problem->AddResidualBlock(make_gps_cost(p.fix->enu, fix_covariance(*p.fix), p.alpha, antenna),
                                nullptr, (*poses)[p.k].data(), (*poses)[p.k + 1].data());
      ++fixes;
    }
    fixes_scale_ = odometry || fixes > 0;
    return fixes > 0;
  }

  bool fixes_scale() const override { return fixes_scale_; }

  std::vector<std::pair<double*, int>> blocks_with_covariance() override {
    return {{&scale_, 1}, {bias_.data(), 3}};
  }
  void take_covariance(const double* block, const Eigen::MatrixXd& covariance) override {
    if (block == &scale_) scale_sigma_ = std::sqrt(covariance(0, 0));
    if (block == bias_.data()) bias_sigma_ = covariance.diagonal().cwiseSqrt();
  }

  double scale() const { return scale_; }
  const Eigen::Vector3d& bias() const { return bias_; }
  double scale_sigma() const { return scale_sigma_; }
  const Eigen::Vector3d& bias_sigma() const { return bias_sigma_; }

 private:
  const MotionSensors& sensors_;
  const std::vector<double>& times_;
  const std::set<int>& refused_;
  const std::vector<int> refused_fixes_;
  double scale_;
  Eigen::Vector3d bias_;
  bool fixes_scale_ = false;
  double scale_sigma_ = NAN;
  Eigen::Vector3d bias_sigma_ = Eigen::Vector3d::Constant(NAN);
};

// The constant gyro bias that best explains the filter's rotations between frames, by linear
// least squares on the gyro residual about zero bias: a starting point for the batch.
Eigen::Vector3d bias_from_filter(const std::vector<FrameMotion>& motions,
                                 const std::vector<Eigen::Isometry3d>& cam_from_world,
                                 const Eigen::Isometry3d& body_from_cam,
                                 const std::set<int>& refused) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d R_bc = body_from_cam.linear();
  for (size_t k = 0; k < motions.size(); ++k) {
    const GyroIncrement& g = motions[k].gyro;
    if (!g.valid || refused.count(static_cast<int>(k) + 1)) continue;
    // r(b) = Log((dR Exp(J b))^T Q) ~= r(0) - J b for the small rotations between frames.
    const Eigen::Matrix3d Q = R_bc * cam_from_world[k].linear() *
                              cam_from_world[k + 1].linear().transpose() * R_bc.transpose();
    const Eigen::Vector3d r0 = so3::log(g.rotation.transpose() * Q);
    normal += g.J_rotation_bias.transpose() * g.J_rotation_bias;
    rhs += g.J_rotation_bias.transpose() * r0;
  }
  if (normal.determinant() <= 0) return Eigen::Vector3d::Zero();
  return normal.ldlt().solve(rhs);
}

// Moves the filter's estimate into the GPS's ENU frame: the similarity (rigid when the scale is
// metric already) that best maps its antenna positions at the fixes' times onto the fixes. Its
// poses are moved as the filter held them (online_cam_from_world, the batch's start), and
// result's world_from_cam made from those.
// The similarity (rigid when `metric`) that best maps the filter's antenna positions at the
// placed fixes onto them.
Eigen::Matrix4d enu_from_filter(const std::vector<FixPlacement>& placed,
                                const std::vector<Eigen::Isometry3d>& online_cam_from_world,
                                const Eigen::Vector3d& antenna, bool metric) {
  Eigen::Matrix3Xd from(3, placed.size()), to(3, placed.size());
  for (size_t i = 0; i < placed.size(); ++i) {
    from.col(i) = antenna_at(online_cam_from_world, placed[i], antenna);
    to.col(i) = placed[i].fix->enu;
  }
  return Eigen::umeyama(from, to, !metric);
}

// The fixes at odds with the rest, as the filter's trajectory (which no fix has moved) places
// them: the worst one taken out and the fit redone while it is beyond kFixOutlierSigmas of its
// own noise and beyond kFixOutlierSpreads times the fixes' robust spread about the fit (the
// filter's drift over a long run leaves good fixes metres off), keeping at least half of them.
std::vector<int> fixes_at_odds(const std::vector<FixPlacement>& all,
                               const std::vector<Eigen::Isometry3d>& online_cam_from_world,
                               const Eigen::Vector3d& antenna, bool metric) {
  // chi-square(3)'s 1 - 1e-6 quantile, as a distance; the robust spread from the median misfit.
  constexpr double kFixOutlierSigmas = 5.54;
  constexpr double kFixOutlierSpreads = 5;
  std::vector<FixPlacement> kept = all;
  std::vector<int> refused;
  while (2 * (kept.size() - 1) >= all.size() && kept.size() > 3) {
    const Eigen::Matrix4d S = enu_from_filter(kept, online_cam_from_world, antenna, metric);
    std::vector<double> misfit_m, sigmas;
    for (const FixPlacement& p : kept) {
      const Eigen::Vector3d from = antenna_at(online_cam_from_world, p, antenna);
      const Eigen::Vector3d misfit =
          S.topLeftCorner<3, 3>() * from + S.topRightCorner<3, 1>() - p.fix->enu;
      misfit_m.push_back(misfit.norm());
      sigmas.push_back(core::mahalanobis(misfit, fix_covariance(*p.fix)));
    }
    const double spread = 1.4826 * core::percentile(misfit_m, 0.5);
    const size_t worst = std::max_element(sigmas.begin(), sigmas.end()) - sigmas.begin();
    if (!(sigmas[worst] > kFixOutlierSigmas && misfit_m[worst] > kFixOutlierSpreads * spread))
      break;
    refused.push_back(kept[worst].index);
    kept.erase(kept.begin() + static_cast<long>(worst));
  }
  std::sort(refused.begin(), refused.end());
  return refused;
}

// Why `placed` cannot fix the ENU frame ("" when they can): fewer than 3 fixes, or all on a line
// within their noise (the rotation about it is not observable); `after` ends the reason's first
// part.
std::string frame_fix_problem(const std::vector<FixPlacement>& placed, const MotionSensors& sensors,
                              const std::string& after) {
  if (placed.size() < 3)
    return "GPS: " + std::to_string(placed.size()) + " fixes within the frames' time span" + after +
           "; at least 3 are needed";
  Eigen::Matrix3Xd to(3, placed.size());
  for (size_t i = 0; i < placed.size(); ++i) to.col(i) = placed[i].fix->enu;
  const Eigen::Matrix3Xd centred = to.colwise() - to.rowwise().mean();
  const Eigen::Vector3d spread = Eigen::JacobiSVD<Eigen::Matrix3Xd>(centred).singularValues();
  const double sigma = sensors.gps.front().horizontal_sigma;
  if (!(spread[1] > 3 * sigma * std::sqrt(static_cast<double>(placed.size()))))
    return "GPS: the fixes lie on a line (within their noise)" + after +
           "; the heading about it cannot be fixed";
  return "";
}

// Moves the estimate into the fixes' ENU frame. Where they cannot place it
// (frame_fix_problem), throws, or with `leave_out` returns false having said why in the result.
bool move_into_enu(const MotionSensors& sensors, const std::vector<double>& times, bool metric,
                   bool leave_out, std::vector<Eigen::Isometry3d>* online_cam_from_world,
                   SfmResult* result) {
  const Eigen::Vector3d antenna = antenna_in_cam(sensors);
  const auto placeable = [&](const std::vector<FixPlacement>& placed, const std::string& after) {
    const std::string problem = frame_fix_problem(placed, sensors, after);
    if (problem.empty()) return true;
    if (!leave_out) throw std::invalid_argument(problem);
    result->gps_left_out = problem;
    result->refused_gps_fixes.clear();
    return false;
  };
  std::vector<FixPlacement> placed = place_fixes(sensors.gps, times);
  if (!placeable(placed, "")) return false;
  result->refused_gps_fixes = fixes_at_odds(placed, *online_cam_from_world, antenna, metric);
  if (!result->refused_gps_fixes.empty()) {
    placed = place_fixes(sensors.gps, times, result->refused_gps_fixes);
    // One fix off a straight path spreads them; without it they may lie on the line again.
    if (!placeable(placed, " once the " + std::to_string(result->refused_gps_fixes.size()) +
                               " at odds with the rest are left out"))
      return false;
  }
  const Eigen::Matrix4d S = enu_from_filter(placed, *online_cam_from_world, antenna, metric);
  const double scale = S.topLeftCorner<3, 3>().col(0).norm();
  const Eigen::Matrix3d R = S.topLeftCorner<3, 3>() / scale;
  const Eigen::Vector3d t = S.topRightCorner<3, 1>();
  for (auto& T : *online_cam_from_world) {
    const Eigen::Vector3d centre = scale * R * (T.inverse().translation()) + t;
    T.linear() = T.linear() * R.transpose();
    T.translation() = -T.linear() * centre;
  }
  result->online_world_from_cam = core::inverted(*online_cam_from_world);
  for (auto& [track, X] : result->online_points) X = scale * R * X + t;
  result->world_is_enu = true;
  return true;
}

void check_timestamps(const std::vector<double>& times, int num_frames) {
  if (static_cast<int>(times.size()) < num_frames)
    throw std::invalid_argument("the tracks span " + std::to_string(num_frames) +
                                " frames but only " + std::to_string(times.size()) +
                                " frame timestamps are given");
  for (int f = 0; f < num_frames; ++f) {
    if (!std::isfinite(times[f]))
      throw std::invalid_argument("frame " + std::to_string(f) + ": timestamp is not a number");
    if (f > 0 && !(times[f] > times[f - 1]))
      throw std::invalid_argument("frame " + std::to_string(f) +
                                  ": timestamp does not increase over the previous frame's");
  }
}

}  // namespace

SfmResult run_fused_sfm(const camera::CatadioptricCamera& camera,
                        const std::vector<core::TrackObservation>& tracks,
                        const std::vector<double>& frame_timestamps, const MotionSensors& sensors,
                        const SfmSettings& settings, const Progress& progress) {
  if (sensors.empty()) return run_sfm(camera, tracks, settings, progress);
  check_settings(camera, settings);
  if (const std::string problem = sensors_problem(sensors); !problem.empty())
    throw std::invalid_argument("MotionSensors: " + problem);
  SfmResult result;
  const std::vector<std::vector<TrackPixel>> by_frame = observations_by_frame(tracks);
  result.num_frames = static_cast<int>(by_frame.size());
  result.num_tracks = tracks_seen_twice(tracks);
  check_timestamps(frame_timestamps, result.num_frames);
  const std::vector<double> times(frame_timestamps.begin(),
                                  frame_timestamps.begin() + result.num_frames);
  const std::vector<FrameMotion> motions = frame_motions(sensors, times, Eigen::Vector3d::Zero());

  std::vector<Eigen::Isometry3d> online_cam_from_world = run_filter(
      camera, by_frame, settings.filter,
      [&](int f, const SensorStates& states) {
        return predict_camera_motion(sensors, times[f - 1], times[f], settings.filter, states);
      },
      progress, &result);
  result.odometry_scale = sensors.odometry_scale;

  refuse_degenerate_motion(result, settings.filter, !sensors.odometry.empty());
  // Fixes that cannot place the estimate, when left out, are out of the batch's terms too.
  MotionSensors without_gps;
  const MotionSensors* terms_sensors = &sensors;
  if (!sensors.gps.empty() &&
      !move_into_enu(sensors, times, !sensors.odometry.empty(), settings.leave_out_unplaceable_gps,
                     &online_cam_from_world, &result)) {
    without_gps = sensors;
    without_gps.gps.clear();
    terms_sensors = &without_gps;
  }
  if (!settings.run_batch) return result;

  const std::set<int> refused(result.refused_motion_frames.begin(),
                              result.refused_motion_frames.end());
  MotionTerms terms(
      *terms_sensors, times,
      bias_from_filter(motions, online_cam_from_world, sensors.body_from_cam, refused), refused,
      result.refused_gps_fixes);
  adjust_on_inliers(camera, tracks, settings, online_cam_from_world, &terms, &result);
  result.odometry_scale = terms.scale();
  result.gyro_bias = terms.bias();
  result.odometry_scale_sigma = terms.scale_sigma();
  result.gyro_bias_sigma = terms.bias_sigma();
  return result;
}

GpsResiduals gps_residuals(const std::vector<Eigen::Isometry3d>& world_from_cam,
                           const std::vector<double>& frame_timestamps,
                           const MotionSensors& sensors, const std::vector<int>& refused_fixes) {
  GpsResiduals r;
  if (frame_timestamps.size() < 2) return r;
  const Eigen::Vector3d antenna = antenna_in_cam(sensors);
  const std::vector<Eigen::Isometry3d> cam_from_world = core::inverted(world_from_cam);
  double sum = 0;
  for (const auto& p : place_fixes(sensors.gps, frame_timestamps, refused_fixes)) {
    sum += (antenna_at(cam_from_world, p, antenna) - p.fix->enu).squaredNorm();
    ++r.fixes;
  }
  if (r.fixes > 0) r.rms_m = std::sqrt(sum / r.fixes);
  return r;
}

}  // namespace omnisfm::sfm
