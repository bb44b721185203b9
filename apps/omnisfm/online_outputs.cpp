#include "online_outputs.h"

#include <stdexcept>

namespace omnisfm::app {

OnlineOutputs::OnlineOutputs(const std::string& dir)
    : dir_(dir),
      trajectory_file_(dir + "/online.tum"),
      points_file_(dir + "/points.vnl"),
      outliers_file_(dir + "/outliers.vnl"),
      trajectory_(trajectory_file_),
      points_writer_(points_file_),
      outliers_writer_(outliers_file_) {}

void OnlineOutputs::attach(sfm::OnlineFilter* filter) {
  filter->on_point_ended([this](int track, const Eigen::Vector3d& p) { point(track, p); });
  filter->on_track_rejected([this](const sfm::RejectedTrack& r) { outlier(r); });
}

void OnlineOutputs::frame(const sfm::OnlineFilter& filter, int frame, double time,
                          int smoothed_start_frames) {
  if (frame >= smoothed_start_frames) return pose(time, filter.cam_from_world());
  waiting_.push_back({frame, time, filter.cam_from_world()});
  if (frame + 1 == smoothed_start_frames) write_waiting(filter);
}

void OnlineOutputs::write_waiting(const sfm::OnlineFilter& filter) {
  for (const Waiting& w : waiting_) {
    const auto smoothed = filter.smoothed_start().find(w.frame);
    pose(w.time, smoothed == filter.smoothed_start().end() ? w.cam_from_world : smoothed->second);
  }
  waiting_.clear();
}

void OnlineOutputs::pose(double timestamp, const Eigen::Isometry3d& cam_from_world) {
  trajectory_.pose({timestamp, cam_from_world.inverse()});
  ++poses_;
}

void OnlineOutputs::point(int track, const Eigen::Vector3d& p) {
  points_writer_.point(track, p);
  ++points_;
}

void OnlineOutputs::outlier(const sfm::RejectedTrack& r) {
  outliers_writer_.outlier(r.track, r.frame);
  ++outliers_;
}

void OnlineOutputs::take_what_is_held(const sfm::OnlineFilter& filter) {
  write_waiting(filter);
  for (const auto& [track, p] : filter.points()) point(track, p);
}

void OnlineOutputs::finish(const std::string& report) {
  trajectory_file_.flush();
  points_file_.flush();
  outliers_file_.flush();
  const bool written = trajectory_file_ && points_file_ && outliers_file_;
  points_file_.close();
  // The PLY header needs the count: the points are read back from points.vnl, a row at a time.
  std::ofstream ply(dir_ + "/points.ply");
  io::write_ply_header(ply, points_);
  io::VnlogReader points(dir_ + "/points.vnl");
  const auto xyz = points.columns({"x", "y", "z"});
  while (points.next())
    ply << points.text(xyz[0]) << ' ' << points.text(xyz[1]) << ' ' << points.text(xyz[2]) << '\n';
  std::ofstream summary(dir_ + "/report.txt");
  summary << report;
  ply.flush();
  summary.flush();
  if (!written || !ply || !summary) throw std::runtime_error(dir_ + ": write failed");
}

}  // namespace omnisfm::app
