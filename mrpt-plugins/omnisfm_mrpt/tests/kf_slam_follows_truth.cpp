// kf_slam_follows_truth KF_SLAM INI SLAM_RAWLOG GROUND_TRUTH_TUM WORK_DIR MAX_PERCENT
//
// Runs stock kf-slam with the shipped INI on the rawlog `omnisfm run --slam-rawlog` wrote, from
// WORK_DIR (its log folder is relative to where it starts), and compares the path it prints (a
// "Mean pose: (x,y,z,qr,qx,qy,qz)=(...)" line per step, the robot's pose) with the truth: each
// robot pose carries the camera at the rawlog's sensorLocationOnRobot, and the cameras' positions,
// rigidly aligned onto the truth, must be within MAX_PERCENT of the distance travelled, with a
// pose for at least 95 % of the frames. Prints the figures; exits 1 when a goal is missed.

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <regex>
#include <string>
#include <vector>

#include "eigen_poses.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/tum_trajectory.h"

namespace {

// The camera's pose on the robot: the first bearing-range observation's sensorLocationOnRobot.
Eigen::Isometry3d body_from_cam(const std::string& rawlog) {
  mrpt::io::CFileGZInputStream file(rawlog);
  auto archive = mrpt::serialization::archiveFrom(file);
  for (;;) {
    const auto object = archive.ReadObject();
    if (auto frame = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(object))
      if (auto landmarks = frame->getObservationByClass<mrpt::obs::CObservationBearingRange>())
        return omnisfm::mrpt_plugin::isometry_of(landmarks->sensorLocationOnRobot);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 7) {
    std::cerr << "usage: kf_slam_follows_truth KF_SLAM INI SLAM_RAWLOG GROUND_TRUTH_TUM WORK_DIR "
                 "MAX_PERCENT\n";
    return 2;
  }
  const std::string kf_slam = argv[1], ini = argv[2], rawlog = argv[3], truth_file = argv[4],
                    work = argv[5];
  const double max_percent = std::stod(argv[6]);
  const std::string log = work + "/kf-slam.log";
  const std::string command = "cd '" + work + "' && '" + kf_slam + "' '" + ini + "' '" + rawlog +
                              "' < /dev/null > '" + log + "' 2>&1";
  if (std::system(command.c_str()) != 0) {
    std::cerr << "kf-slam failed; its output is in " << log << "\n";
    return 1;
  }

  const Eigen::Isometry3d cam_on_robot = body_from_cam(rawlog);
  const std::regex mean_pose(
      R"(Mean pose: \(x,y,z,qr,qx,qy,qz\)=\(([^,]+),([^,]+),([^,]+),([^,]+),([^,]+),([^,]+),([^,]+)\))");
  std::vector<Eigen::Isometry3d> estimate;
  std::ifstream in(log);
  for (std::string line; std::getline(in, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, mean_pose)) continue;
    Eigen::Isometry3d robot = Eigen::Isometry3d::Identity();
    robot.translation() << std::stod(m[1]), std::stod(m[2]), std::stod(m[3]);
    robot.linear() =
        Eigen::Quaterniond(std::stod(m[4]), std::stod(m[5]), std::stod(m[6]), std::stod(m[7]))
            .normalized()
            .toRotationMatrix();
    estimate.push_back(robot * cam_on_robot);
  }
  std::vector<Eigen::Isometry3d> truth;
  for (const auto& pose : omnisfm::io::read_tum_trajectory(truth_file))
    truth.push_back(pose.world_from_cam);

  const double pose_fraction = static_cast<double>(estimate.size()) / truth.size();
  std::cout << "kf-slam: " << estimate.size() << " poses for " << truth.size() << " frames\n";
  if (estimate.size() > truth.size() || pose_fraction < 0.95 || estimate.size() < 3) {
    std::cerr << "kf-slam gave a pose for " << 100 * pose_fraction
              << " % of the frames (at least 95 %)\n";
    return 1;
  }
  truth.resize(estimate.size());
  const omnisfm::eval::TrajectoryErrors errors =
      omnisfm::eval::trajectory_errors(estimate, truth, false);
  std::printf("kf-slam path after a rigid alignment: mean %.4f m, %.3f %% of %.2f m, rotation "
              "%.3f deg\n",
              errors.mean_translation_error_m, errors.translation_error_percent,
              errors.distance_travelled_m, errors.mean_rotation_error_deg);
  if (!(errors.translation_error_percent <= max_percent)) {
    std::cerr << "more than " << max_percent << " % of the distance\n";
    return 1;
  }
  return 0;
}
