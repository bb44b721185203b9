#include "sfm_outputs.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/outliers_file.h"
#include "omnisfm/io/points_file.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "residual_plots.h"
#ifdef OMNISFM_WITH_MRPT_PLUGIN
#include "omnisfm/mrpt_plugin/pose_graph_file.h"
#endif

namespace omnisfm::app {
namespace {

std::vector<io::StampedPose> trajectory(const std::vector<Eigen::Isometry3d>& world_from_cam,
                                        const std::vector<double>& times) {
  std::vector<io::StampedPose> out;
  for (size_t f = 0; f < world_from_cam.size(); ++f) out.push_back({times[f], world_from_cam[f]});
  return out;
}

}  // namespace

std::string compare_written_online_with_truth(const std::string& dir,
                                              const std::vector<io::StampedPose>& truth,
                                              const std::string& truth_file, bool rigid_too) {
  sfm::SfmResult result;
  for (const auto& p : io::read_tum_trajectory(dir + "/online.tum"))
    result.online_world_from_cam.push_back(p.world_from_cam);
  result.num_frames = static_cast<int>(result.online_world_from_cam.size());
  const eval::TruthComparison comparison =
      eval::compare_with_truth(result, false, truth, truth_file, rigid_too);
  std::ofstream report(dir + "/report.txt", std::ios::app);
  report << comparison.report;
  if (!report.flush()) throw std::runtime_error(dir + ": write failed");
  if (!write_trajectory_plots(dir, comparison.truth, comparison.estimates))
    std::cerr << "omnisfm: gnuplot failed: plots missing\n";
  return comparison.report;
}

void write_refined_camera(const std::string& dir, const camera::CatadioptricCamera& camera,
                          const sfm::BatchResult& batch, const sfm::BatchSettings& settings) {
  if (!batch.camera_refined) return;
  camera::CatadioptricCamera refined = camera;
  if (!refined.set_params(batch.camera_params))
    throw std::runtime_error("the batch's refined camera is not a valid camera");
  const std::string path = dir + "/camera_refined.ini";
  if (batch.camera_covariance.size() == 0) {
    io::write_camera_file(path, refined);
    return;
  }
  io::ParameterCovariance covariance;
  const std::vector<std::string> names = camera.param_names();
  for (int p : settings.camera_prior.parameters) covariance.parameters.push_back(names[p]);
  covariance.matrix = batch.camera_covariance;
  io::write_calibrated_camera_file(path, refined, covariance);
}

void write_sfm_outputs(const std::string& dir, const sfm::SfmResult& result, bool batch_ran,
                       const std::vector<double>& times, const std::string& report) {
  io::write_tum_trajectory(dir + "/online.tum", trajectory(result.online_world_from_cam, times));
  const auto& points = batch_ran ? result.batch.points : result.online_points;
  if (batch_ran)
    io::write_tum_trajectory(dir + "/batch.tum", trajectory(result.batch.world_from_cam, times));
#ifdef OMNISFM_WITH_MRPT_PLUGIN
  if (batch_ran && !result.batch.cam_from_world_covariances.empty()) {
    // The graph is a view of the batch for MRPT's tools: without it the results still stand.
    try {
      mrpt_plugin::write_pose_graph(dir + "/batch.graph", result.batch);
      mrpt_plugin::write_pose_graph(dir + "/batch.graphbin", result.batch);
    } catch (const std::runtime_error& e) {
      std::cerr << "omnisfm: warning: batch.graph and batch.graphbin not written: " << e.what()
                << "\n";
    }
  }
#endif
  std::ofstream table(dir + "/points.vnl");
  io::PointsTableWriter points_table(table);
  for (const auto& [track, X] : points) points_table.point(track, X);
  std::ofstream ply(dir + "/points.ply");
  io::write_ply_header(ply, static_cast<long>(points.size()));
  for (const auto& [track, X] : points) io::write_ply_point(ply, X);
  std::ofstream outliers(dir + "/outliers.vnl");
  io::OutliersTableWriter outliers_table(outliers);
  for (const auto& r : result.outliers) outliers_table.outlier(r.track, r.frame);
  std::ofstream summary(dir + "/report.txt");
  summary << report;
  table.flush();
  ply.flush();
  outliers.flush();
  summary.flush();
  if (!table || !ply || !outliers || !summary) throw std::runtime_error(dir + ": write failed");
}

void write_sfm_plots(const std::string& dir, const camera::CatadioptricCamera& camera,
                     const std::vector<core::TrackObservation>& tracks,
                     const sfm::SfmResult& result, bool batch_ran,
                     const eval::TruthComparison& comparison) {
  const bool residuals_plotted = write_residual_plots(dir, camera, tracks, result, batch_ran);
  const bool trajectories_plotted =
      comparison.estimates.empty() ||
      write_trajectory_plots(dir, comparison.truth, comparison.estimates);
  if (!residuals_plotted || !trajectories_plotted)
    std::cerr << "omnisfm: gnuplot failed: plots missing\n";
}

}  // namespace omnisfm::app
