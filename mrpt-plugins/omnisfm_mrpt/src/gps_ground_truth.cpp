#include "omnisfm/mrpt_plugin/gps_ground_truth.h"

#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/mrpt_plugin/geodetic_table.h"

namespace omnisfm::mrpt_plugin {

void write_gps_ground_truth(const sim::Dataset& dataset, const sim::GpsTrack& gps,
                            double start_time, const std::string& dir) {
  const LocalEnuFrame enu({gps.latitude_deg, gps.longitude_deg, gps.height_m});
  std::vector<io::StampedPose> enu_truth;
  for (std::size_t f = 0; f < dataset.world_from_cam.size(); ++f)
    enu_truth.push_back(
        {start_time + dataset.timestamps[f], gps.enu_from_world * dataset.world_from_cam[f]});
  io::write_tum_trajectory(dir + "/ground_truth_enu.tum", enu_truth);
  std::vector<double> times;
  std::vector<Eigen::Vector3d> centres;
  for (const io::StampedPose& pose : enu_truth) {
    times.push_back(pose.timestamp);
    centres.push_back(pose.world_from_cam.translation());
  }
  write_geodetic_table(dir + "/ground_truth_geodetic.vnl", times, centres, enu,
                       "the true camera centre per frame");
}

}  // namespace omnisfm::mrpt_plugin
