#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sfm/settings_file.h"
#include "output_folder.h"
#include "sfm_outputs.h"
#include "verb_inputs.h"
#include "terminal_progress.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

// Frame times from frames.vnl beside the tracks, else the frame indices.
std::vector<double> frame_times(const std::string& tracks_path, int num_frames) {
  std::vector<double> times(num_frames);
  for (int f = 0; f < num_frames; ++f) times[f] = f;
  const fs::path frames = fs::path(tracks_path).parent_path() / "frames.vnl";
  if (!fs::exists(frames)) return times;
  const io::VnlogTable table = io::VnlogTable::read(frames.string());
  const auto cols = table.columns({"frame", "timestamp"});
  for (size_t r = 0; r < table.num_rows(); ++r) {
    const double f = table.number(r, cols[0]);
    if (f >= 0 && f < num_frames && f == static_cast<int>(f))
      times[static_cast<int>(f)] = table.number(r, cols[1]);
  }
  return times;
}

}  // namespace

void add_sfm_verb(CLI::App& app) {
  struct Options {
    std::string camera, tracks, out, config, ground_truth;
  };
  auto o = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "sfm",
      "Shape-from-motion from tracks: the online filter then the batch adjustment; writes "
      "online.tum, batch.tum, points.vnl, points.ply, outliers.vnl, report.txt and the residual "
      "plots (residuals.png, residuals_per_frame.png); with --ground-truth also the paper's "
      "figures and trajectory plots (motion.png, path.png)");
  verb->add_option("--camera", o->camera, "Camera file (default: the shipped equiangular)");
  verb->add_option("--tracks", o->tracks, "tracks.vnl (# frame track u v)")->required();
  verb->add_option("--out", o->out, "Output folder (replaced whole when it exists)")->required();
  verb->add_option("--config", o->config,
                   "Settings: an INI file with an [sfm] section (the shipped config/omnisfm.ini "
                   "holds every key at its default)");
  verb->add_option("--ground-truth", o->ground_truth,
                   "A TUM trajectory of the truth: adds the paper's error figures to the report");
  verb->callback([o] {
    const camera::CatadioptricCamera camera = load_camera(o->camera);
    const auto tracks = io::read_tracks(o->tracks, camera.image_width(), camera.image_height());
    const sfm::SfmSettings settings =
        o->config.empty() ? sfm::SfmSettings() : sfm::read_sfm_settings(o->config);
    std::vector<io::StampedPose> truth;
    if (!o->ground_truth.empty()) truth = io::read_tum_trajectory(o->ground_truth);

    sfm::SfmResult result;
    try {
      TerminalProgress progress("filter", "frames");
      result = sfm::run_sfm(camera, tracks, settings, progress.callback());
    } catch (const std::invalid_argument& e) {
      throw io::InputError(o->tracks, 0, e.what());
    }
    if (settings.run_batch && !result.batch.converged && result.batch.cam_from_world.empty())
      throw std::runtime_error("the batch adjustment failed: " + result.batch.message);

    const std::vector<double> times = frame_times(o->tracks, result.num_frames);
    std::ostringstream report;
    report << "frames " << result.num_frames << ", observations " << tracks.size()
           << ", outlier tracks " << result.outliers.size() << "\n"
           << "filter: " << result.online_seconds << " s ("
           << 1000 * result.online_seconds / result.num_frames << " ms per frame)\n";
    if (settings.run_batch)
      report << "batch: " << (result.batch.converged ? "converged" : "did not converge") << " in "
             << result.batch.iterations << " iterations, " << result.batch.solve_seconds
             << " s; RMS " << result.batch.initial_rms_px << " -> " << result.batch.final_rms_px
             << " px per coordinate (" << result.batch.message << ")\n";
    TruthComparison comparison;
    if (!truth.empty()) {
      comparison = compare_with_truth(result, settings.run_batch, truth, o->ground_truth);
      report << comparison.report;
    }

    write_folder(o->out, [&](const std::string& dir) {
      write_sfm_outputs(dir, result, settings.run_batch, times, report.str());
      write_sfm_plots(dir, camera, tracks, result, settings.run_batch, comparison);
    });
    std::cout << report.str();
  });
}

void add_eval_verb(CLI::App& app) {
  struct Options {
    std::string estimate, ground_truth;
    bool rigid = false;
  };
  auto o = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "eval", "The paper's error figures of a TUM trajectory against ground truth, after Horn's "
              "alignment (a similarity, or rigid with --rigid)");
  verb->add_option("--estimate", o->estimate, "Estimated trajectory (TUM)")->required();
  verb->add_option("--ground-truth", o->ground_truth, "True trajectory (TUM)")->required();
  verb->add_flag("--rigid", o->rigid, "Align without scale (when the scale is known)");
  verb->callback([o] {
    const auto estimate = io::read_tum_trajectory(o->estimate);
    const auto truth = io::read_tum_trajectory(o->ground_truth);
    // Poses are paired by timestamp.
    std::vector<Eigen::Isometry3d> a, b;
    size_t j = 0;
    for (const auto& p : estimate) {
      while (j < truth.size() && truth[j].timestamp < p.timestamp - 1e-6) ++j;
      if (j < truth.size() && std::abs(truth[j].timestamp - p.timestamp) <= 1e-6) {
        a.push_back(p.world_from_cam);
        b.push_back(truth[j].world_from_cam);
      }
    }
    if (a.size() < 3) {
      // Often two clocks: a rawlog replay's (1e9 s on) against a simulation's (0 on).
      const auto span = [](const std::vector<io::StampedPose>& poses) {
        std::ostringstream text;
        text << std::setprecision(12);
        if (poses.empty()) return std::string("none");
        text << poses.front().timestamp << " .. " << poses.back().timestamp;
        return text.str();
      };
      throw io::InputError(o->estimate, 0,
                           "fewer than 3 timestamps in common with " + o->ground_truth +
                               " (timestamps " + span(estimate) + " against " + span(truth) +
                               "; `run --ground-truth` pairs poses by frame instead)");
    }
    const eval::TrajectoryErrors e = eval::trajectory_errors(a, b, !o->rigid);
    std::cout << "poses " << a.size() << "\n" << figures_line(o->rigid ? "rigid" : "similar", e);
  });
}

}  // namespace omnisfm::app
