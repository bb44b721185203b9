#include "residual_plots.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "omnisfm/io/gnuplot.h"
#include "omnisfm/core/percentile.h"
#include "omnisfm/io/residual_vectors_plot.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::app {
namespace {

// Per frame: the inliers' RMS (per coordinate) and largest residual, and how many outlier
// observations it has.
void write_per_frame(const std::string& path, const std::vector<sfm::ObservationResidual>& rs) {
  struct Frame {
    double sum_sq = 0, worst = 0;
    int inliers = 0, outliers = 0;
  };
  std::map<int, Frame> frames;
  for (const auto& r : rs) {
    Frame& f = frames[r.frame];
    if (r.outlier) {
      ++f.outliers;
      continue;
    }
    f.sum_sq += r.residual.squaredNorm();
    f.worst = std::max(f.worst, r.residual.norm());
    ++f.inliers;
  }
  std::ofstream out(path);
  io::VnlogWriter writer(out, {"frame", "rms", "worst", "inliers", "outliers"});
  for (const auto& [frame, f] : frames)
    writer.row({double(frame), f.inliers ? std::sqrt(f.sum_sq / (2.0 * f.inliers)) : 0.0, f.worst,
                double(f.inliers), double(f.outliers)});
  if (!out.flush()) throw std::runtime_error(path + ": write failed");
}

std::string vectors_script(int w, int h, double scale, bool with_outliers) {
  io::ResidualVectorsPlot plot;
  plot.image_width = w, plot.image_height = h;
  plot.scale = scale;
  plot.title = "Reprojection residuals";
  plot.x_column = 3, plot.y_column = 4, plot.du_column = 5, plot.dv_column = 6;
  plot.outlier_column = 7;
  plot.inlier_label = "inlier tracks";
  plot.outlier_label = with_outliers ? "outlier tracks" : "";
  plot.arrow_heads = false;
  return io::residual_vectors_script(plot);
}

std::string per_frame_script(bool with_outliers) {
  std::string gp =
      "# The inliers' residuals per frame, and the outlier tracks' observations.\n"
      "set terminal pngcairo size 1000,600 font 'sans,11'\n"
      "set output 'residuals_per_frame.png'\n"
      "set xlabel 'frame'\nset ylabel 'residual (pixels)'\n"
      "set key outside bottom center horizontal\n"
      "set title 'Reprojection residuals per frame'\n";
  if (with_outliers) gp += "set ytics nomirror\nset y2tics\nset y2label 'outlier observations'\n";
  gp +=
      "plot 'residuals_per_frame.vnl' using 1:2 with lines lw 2 lc rgb '#1f4e9e' "
      "title 'inlier RMS per coordinate', \\\n"
      "     '' using 1:3 with lines lc rgb '#ff7f0e' title 'largest inlier residual'";
  if (with_outliers)
    gp += ", \\\n     '' using 1:5 axes x1y2 with impulses lc rgb '#d62728' "
          "title 'outlier observations'";
  return gp + "\n";
}

// Writes `script` into `dir` and draws it.
bool draw(const std::string& dir, const std::string& script, const std::string& text) {
  std::ofstream(dir + "/" + script) << text;
  return io::run_gnuplot(dir, script);
}

}  // namespace

bool write_residual_plots(const std::string& dir, int image_width, int image_height,
                          const std::vector<sfm::ObservationResidual>& residuals) {
  std::ofstream out(dir + "/residuals.vnl");
  io::VnlogWriter writer(out, {"frame", "track", "x", "y", "du", "dv", "outlier"});
  writer.comment("residual (du, dv) = projected - observed pixel (x, y)");
  std::vector<double> inlier_norms;
  bool any_outlier = false;
  for (const auto& r : residuals) {
    writer.row({double(r.frame), double(r.track), r.pixel.x(), r.pixel.y(), r.residual.x(),
                r.residual.y(), r.outlier ? 1.0 : 0.0});
    if (!r.outlier) inlier_norms.push_back(r.residual.norm());
    any_outlier = any_outlier || r.outlier;
  }
  if (!out.flush()) throw std::runtime_error(dir + "/residuals.vnl: write failed");
  write_per_frame(dir + "/residuals_per_frame.vnl", residuals);
  // The 99th-percentile inlier residual drawn as 4 % of the image width.
  const double typical = std::max(core::percentile(inlier_norms, 0.99), 1e-3);
  const double scale = std::max(1.0, io::round_down_125(0.04 * image_width / typical));
  const bool vectors = draw(dir, "residuals.gp", vectors_script(image_width, image_height, scale, any_outlier));
  const bool per_frame = draw(dir, "residuals_per_frame.gp", per_frame_script(any_outlier));
  return vectors && per_frame;
}

bool write_residual_plots(const std::string& dir, const camera::CatadioptricCamera& camera,
                          const std::vector<core::TrackObservation>& tracks,
                          const sfm::SfmResult& result, bool batch_ran) {
  std::set<int> outliers;
  for (const auto& o : result.outliers) outliers.insert(o.track);
  std::map<int, Eigen::Vector3d> points = batch_ran ? result.batch.points : result.online_points;
  for (int track : outliers) {
    const auto online = result.online_points.find(track);
    if (online != result.online_points.end()) points.emplace(track, online->second);
  }
  const auto& world_from_cam =
      batch_ran ? result.batch.world_from_cam : result.online_world_from_cam;
  // The batch's residuals with the camera it optimised with (its patch reaches past the rim).
  const camera::CatadioptricCamera judged = batch_ran ? sfm::batch_camera(camera) : camera;
  return write_residual_plots(
      dir, camera.image_width(), camera.image_height(),
      sfm::reprojection_residuals(judged, tracks, world_from_cam, points, outliers));
}

}  // namespace omnisfm::app
