#pragma once
// Trajectories in the TUM text format: one line per frame, `timestamp tx ty tz qx qy qz qw`, the
// pose world_from_cam; lines starting with '#' are comments.

#include <Eigen/Geometry>
#include <iosfwd>
#include <string>
#include <vector>

namespace omnisfm::io {

struct StampedPose {
  double timestamp = 0;
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
};

// Throws InputError naming the file and line for a malformed line, a non-unit quaternion
// (|q| off 1 by more than 1e-3) or timestamps that do not increase.
std::vector<StampedPose> read_tum_trajectory(const std::string& path);

// Writes a trajectory pose by pose, for sequences too long to hold: the header at construction,
// then one line per pose.
class TumTrajectoryWriter {
 public:
  explicit TumTrajectoryWriter(std::ostream& out);
  void pose(const StampedPose& pose);

 private:
  std::ostream& out_;
};

// Writes atomically; throws std::runtime_error when it cannot.
void write_tum_trajectory(const std::string& path, const std::vector<StampedPose>& trajectory);

}  // namespace omnisfm::io
