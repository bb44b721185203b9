#include "omnisfm/io/tum_trajectory.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::io {

std::vector<StampedPose> read_tum_trajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open the trajectory");
  std::vector<StampedPose> poses;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream fields(text);
    std::string field;
    std::vector<double> values;
    while (fields >> field) {
      if (values.empty() && field[0] == '#') break;
      double v;
      if (!parse_double(field, &v) || !std::isfinite(v))
        throw InputError(path, line, "'" + field + "' is not a finite number");
      values.push_back(v);
    }
    if (values.empty()) continue;
    if (values.size() != 8)
      throw InputError(path, line,
                       "expected 8 fields (timestamp tx ty tz qx qy qz qw), found " +
                           std::to_string(values.size()));
    const Eigen::Quaterniond q(values[7], values[4], values[5], values[6]);
    if (std::abs(q.norm() - 1) > 1e-3)
      throw InputError(path, line, "the quaternion is not of unit length");
    if (!poses.empty() && !(values[0] > poses.back().timestamp))
      throw InputError(path, line, "timestamps must increase");
    StampedPose pose;
    pose.timestamp = values[0];
    pose.world_from_cam.linear() = q.normalized().toRotationMatrix();
    pose.world_from_cam.translation() << values[1], values[2], values[3];
    poses.push_back(pose);
  }
  return poses;
}

TumTrajectoryWriter::TumTrajectoryWriter(std::ostream& out) : out_(out) {
  out_ << "# timestamp tx ty tz qx qy qz qw\n";
}

void TumTrajectoryWriter::pose(const StampedPose& pose) {
  const Eigen::Quaterniond q(pose.world_from_cam.linear());
  const Eigen::Vector3d& t = pose.world_from_cam.translation();
  out_ << format_double(pose.timestamp) << ' ' << format_double(t.x()) << ' '
       << format_double(t.y()) << ' ' << format_double(t.z()) << ' ' << format_double(q.x())
       << ' ' << format_double(q.y()) << ' ' << format_double(q.z()) << ' '
       << format_double(q.w()) << '\n';
}

void write_tum_trajectory(const std::string& path, const std::vector<StampedPose>& trajectory) {
  write_text_atomically(path, [&](std::ostream& out) {
    TumTrajectoryWriter writer(out);
    for (const auto& pose : trajectory) writer.pose(pose);
  });
}

}  // namespace omnisfm::io
