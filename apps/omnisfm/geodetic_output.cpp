#include "geodetic_output.h"

#include <algorithm>
#include <cmath>

#include "omnisfm/mrpt_plugin/geodetic_table.h"

namespace omnisfm::app {
namespace {

// world_from_cam at time t, between the frames around it (positions linear, rotations slerped).
Eigen::Isometry3d pose_at(const std::vector<Eigen::Isometry3d>& poses,
                          const std::vector<double>& times, double t) {
  const auto after = std::upper_bound(times.begin(), times.end(), t);
  if (after == times.begin()) return poses.front();
  if (after == times.end()) return poses.back();
  const std::size_t k = static_cast<std::size_t>(after - times.begin());
  const double a = (t - times[k - 1]) / (times[k] - times[k - 1]);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(poses[k - 1].linear())
                   .slerp(a, Eigen::Quaterniond(poses[k].linear()))
                   .toRotationMatrix();
  T.translation() = (1 - a) * poses[k - 1].translation() + a * poses[k].translation();
  return T;
}

}  // namespace

GpsFit gps_fit_of(const std::vector<Eigen::Isometry3d>& world_from_cam,
                  const std::vector<double>& frame_times, const sfm::MotionSensors& sensors) {
  const Eigen::Isometry3d cam_from_body = sensors.body_from_cam.inverse();
  GpsFit fit;
  double sum = 0;
  for (const sfm::GpsSample& fix : sensors.gps) {
    if (frame_times.empty() || fix.timestamp < frame_times.front() ||
        fix.timestamp > frame_times.back())
      continue;
    const Eigen::Vector3d antenna = pose_at(world_from_cam, frame_times, fix.timestamp) *
                                    (cam_from_body * sensors.antenna_in_body);
    sum += (antenna - fix.enu).squaredNorm();
    ++fit.fixes;
  }
  if (fit.fixes > 0) fit.rms_m = std::sqrt(sum / fit.fixes);
  return fit;
}

void write_geodetic_trajectory(const std::string& path,
                               const std::vector<Eigen::Isometry3d>& world_from_cam,
                               const std::vector<double>& frame_times,
                               const mrpt_plugin::LocalEnuFrame& enu) {
  std::vector<Eigen::Vector3d> centres;
  for (const Eigen::Isometry3d& T : world_from_cam) centres.push_back(T.translation());
  mrpt_plugin::write_geodetic_table(path, frame_times, centres, enu,
                                    "the estimated camera centre per frame");
}

}  // namespace omnisfm::app
