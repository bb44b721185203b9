#include "geodetic_output.h"

#include "omnisfm/mrpt_plugin/geodetic_table.h"

namespace omnisfm::app {

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
