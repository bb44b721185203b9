#pragma once
// What an online-only run (`[sfm] batch = false`) writes as it goes, so that a sequence of any
// length takes constant memory: online.tum a pose per frame, points.vnl a point as its track ends
// (and the live ones at the end), outliers.vnl a track as it is rejected; at the end points.ply,
// made from points.vnl, and report.txt.

#include <Eigen/Geometry>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "omnisfm/io/outliers_file.h"
#include "omnisfm/io/points_file.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/sfm/online_filter.h"

namespace omnisfm::app {

class OnlineOutputs {
 public:
  // Into the existing folder `dir`.
  explicit OnlineOutputs(const std::string& dir);

  // The filter's ended points and rejected tracks go straight to the files; set its
  // kept_history to 0, since nothing needs them kept.
  void attach(sfm::OnlineFilter* filter);
  // The filter's pose after it processed `frame` (counting from 0, every frame); the first
  // smoothed_start_frames wait until the smoothed start has revised them.
  void frame(const sfm::OnlineFilter& filter, int frame, double time,
             int smoothed_start_frames);
  void pose(double timestamp, const Eigen::Isometry3d& cam_from_world);
  void point(int track, const Eigen::Vector3d& point);
  void outlier(const sfm::RejectedTrack& rejected);

  // At the end of the sequence, while the filter still exists: the poses still waiting and the
  // points it still holds.
  void take_what_is_held(const sfm::OnlineFilter& filter);
  // points.ply and report.txt; throws std::runtime_error naming the folder when any write failed.
  void finish(const std::string& report);

  long poses() const { return poses_; }
  long points() const { return points_; }
  long outliers() const { return outliers_; }

 private:
  std::string dir_;
  std::ofstream trajectory_file_, points_file_, outliers_file_;
  io::TumTrajectoryWriter trajectory_;
  io::PointsTableWriter points_writer_;
  io::OutliersTableWriter outliers_writer_;
  struct Waiting {
    int frame;
    double time;
    Eigen::Isometry3d cam_from_world;
  };
  std::vector<Waiting> waiting_;
  void write_waiting(const sfm::OnlineFilter& filter);
  long poses_ = 0, points_ = 0, outliers_ = 0;
};

}  // namespace omnisfm::app
