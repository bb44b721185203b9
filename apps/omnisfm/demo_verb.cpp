// The main job, end to end on the embedded default: the paper's three experiments simulated and
// rendered through the mirror, features tracked in the rendered images, shape-from-motion on
// those tracks, and the paper's error figures next to the paper's own and next to the same
// estimators run on the simulator's own tracks; the tracks' accuracy against the truth; plots.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "image_threads.h"
#include "omnisfm/eval/track_accuracy.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sfm/sfm_report.h"
#include "omnisfm/sim/dataset_writer.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/imaging.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/track/frames_file.h"
#include "omnisfm/track/image_sequence.h"
#include "omnisfm/track/track_images.h"
#include "omnisfm/track/track_lengths.h"
#include "residual_plots.h"
#include "sfm_outputs.h"
#include "terminal_progress.h"
#include "trajectory_plots.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

struct PaperFigures {
  const char* scenario;
  const char* rotation_kind;  // which rotation figure the paper gives
  double translation_percent, rotation_deg;
};

constexpr PaperFigures kPaper[] = {
    {"lab", "rotation spread", 0.12, 0.40},
    {"crane", "rotation", 0.79, 1.61},
    {"rover", "yaw", 1.02, 0.48},
};

double rotation_figure(const char* kind, const eval::TrajectoryErrors& e) {
  const std::string k = kind;
  if (k == "yaw") return e.mean_yaw_error_deg;
  if (k == "rotation spread") return e.rotation_spread_deg;
  return e.mean_rotation_error_deg;
}

// "SCENARIO: WHAT", as the progress line names the work.
std::string step(const char* scenario, const char* what) {
  return std::string(scenario) + ": " + what;
}

sfm::SfmResult shape_from_motion(const sim::Dataset& d,
                                 const std::vector<core::TrackObservation>& tracks,
                                 const std::string& what) {
  sfm::SfmSettings settings;
  settings.batch.covariances = false;
  TerminalProgress progress(what, "frames");
  sfm::SfmResult result = sfm::run_sfm(d.camera, tracks, settings, progress.callback());
  if (!result.batch.usable())
    throw std::runtime_error(what + ": the batch adjustment failed: " + result.batch.message);
  return result;
}

// The experiment's dataset with its images rendered into dir/dataset.
void render_dataset(const sim::Dataset& d, const PaperFigures& paper, std::uint64_t seed,
                    const std::string& imaging, const fs::path& dir) {
  sim::Renderer renderer(d.camera, 4, renderer_threads());
  sim::Imaging camera(sim::ImagingSettings::named(imaging), &renderer, seed);
  const int frames = static_cast<int>(d.world_from_cam.size());
  TerminalProgress rendering(step(paper.scenario, "rendered"), "images");
  sim::write_dataset(d, (dir / "dataset").string(), [&](int frame, const std::string& path) {
    sim::write_png(path, camera.record(d, frame));
    rendering(frame + 1, frames);
  });
}

// From pixels: the rendered images tracked, as `omnisfm track` does, into dir/track.
track::TrackedSequence track_rendered(const sim::Dataset& d, const PaperFigures& paper,
                                      const std::string& imaging, const fs::path& dir) {
  track::ImageSequence images((dir / "dataset" / "images").string());
  TerminalProgress tracking_progress(step(paper.scenario, "tracked"), "images");
  // The tracker told the rendered camera's blur, as a user tells it a real camera's.
  track::TrackerSettings settings;
  settings.camera_blur_px = sim::ImagingSettings::named(imaging).blur_px();
  track::TrackedSequence tracked =
      track::track_images(d.camera, images, settings, tracking_progress.callback());
  for (track::TrackedFrame& f : tracked.frames) f.timestamp = d.timestamps[f.index];
  fs::create_directories(dir / "track");
  track::write_frames_file((dir / "track" / "frames.vnl").string(), tracked.frames);
  io::write_tracks((dir / "track" / "tracks.vnl").string(), tracked.observations);
  return tracked;
}

// An experiment's rows of the summary's two tables.
struct ExperimentRows {
  std::string motion, tracking;
};

// One of the paper's experiments from simulation to figures, its outputs under root/<scenario>.
ExperimentRows run_experiment(const PaperFigures& paper, std::uint64_t seed,
                              const std::string& imaging, const fs::path& root) {
  sim::SimulationOptions options;
  options.scenario = paper.scenario;
  options.seed = seed;
  const sim::Dataset d = sim::simulate(options);
  const fs::path dir = root / paper.scenario;
  fs::create_directories(dir);
  render_dataset(d, paper, seed, imaging, dir);
  const track::TrackedSequence tracked = track_rendered(d, paper, imaging, dir);
  const eval::TrackAccuracy accuracy = eval::track_accuracy(d, tracked.observations);

  // The same estimators on the simulator's tracks (Gaussian noise, known mistracks): what the
  // tracking costs.
  const sfm::SfmResult simulated =
      shape_from_motion(d, d.observations, step(paper.scenario, "filter on simulated tracks"));
  const auto simulated_batch =
      eval::trajectory_errors(simulated.batch.world_from_cam, d.world_from_cam, true);

  const sfm::SfmResult r =
      shape_from_motion(d, tracked.observations, step(paper.scenario, "filter on tracked images"));
  const auto online = eval::trajectory_errors(r.online_world_from_cam, d.world_from_cam, true);
  const auto batch = eval::trajectory_errors(r.batch.world_from_cam, d.world_from_cam, true);
  // Outliers as shape-from-motion sees them: tracks that leave their point by more than its
  // 2-pixel rejection threshold.
  std::set<int> found;
  for (const auto& o : r.outliers) found.insert(o.track);
  const auto far_off = eval::track_accuracy(d, tracked.observations, 2.0).mistracked;
  const auto outliers =
      eval::outlier_detection(found, std::set<int>(far_off.begin(), far_off.end()));

  std::ostringstream report;
  report << sfm::scale_line(r, sfm::BatchSettings()) << eval::figures_line("online", online)
         << eval::figures_line("batch", batch);
  fs::create_directories(dir / "sfm");
  write_sfm_outputs((dir / "sfm").string(), r, true, d.timestamps, report.str());
  const bool residuals_plotted =
      write_residual_plots((dir / "sfm").string(), d.camera, tracked.observations, r, true);
  const bool trajectories_plotted = write_trajectory_plots(
      (dir / "sfm").string(), d.world_from_cam,
      {{"online", r.online_world_from_cam, online.alignment},
       {"batch", r.batch.world_from_cam, batch.alignment}});
  const bool plotted = residuals_plotted && trajectories_plotted;

  ExperimentRows rows;
  char line[256];
  std::snprintf(line, sizeof line,
                "%-11s translation      %6.2f %%    %6.3f %%    %6.3f %%    %6.3f %%    %d/%d\n",
                paper.scenario, paper.translation_percent,
                simulated_batch.translation_error_percent, online.translation_error_percent,
                batch.translation_error_percent, outliers.correct, outliers.actual);
  rows.motion = line;
  std::snprintf(line, sizeof line, "%-11s %-16s %6.2f deg  %6.3f deg  %6.3f deg  %6.3f deg%s\n",
                "", paper.rotation_kind, paper.rotation_deg,
                rotation_figure(paper.rotation_kind, simulated_batch),
                rotation_figure(paper.rotation_kind, online),
                rotation_figure(paper.rotation_kind, batch),
                plotted ? "" : "   (no gnuplot: no plots)");
  rows.motion += line;
  const auto& s = tracked.statistics;
  std::snprintf(line, sizeof line,
                "%-11s %6d  %6d  %3d fr    %5.3f px  %5.3f px  %5d       %5d (%d)           %5.1f\n",
                paper.scenario, s.frames, accuracy.tracks,
                track::track_lengths(tracked.observations).median_frames, accuracy.median_px,
                accuracy.p95_px, accuracy.mistracked_tracks, accuracy.reacquisitions,
                accuracy.wrong_reacquisitions,
                1000 * tracked.tracking_seconds / std::max(1, s.frames));
  rows.tracking = line;
  return rows;
}

}  // namespace

void add_demo_verb(CLI::App& app) {
  auto out = std::make_shared<std::string>("out");
  auto seed = std::make_shared<std::uint64_t>(1);
  auto imaging = std::make_shared<std::string>("realistic");
  CLI::App* verb = app.add_subcommand(
      "demo",
      "The main job: the paper's lab, crane and rover experiments simulated and rendered through "
      "the mirror, features tracked in the images, shape-from-motion on the tracks, and the error "
      "figures next to the paper's");
  verb->add_option("--out", *out,
                   "Output folder: made, or replaced whole when an earlier omnisfm run wrote it (a "
                   "folder holding other files, or the inputs, is refused)")
      ->capture_default_str();
  verb->add_option("--seed", *seed, "Random seed of the simulations")
      ->capture_default_str()
      ->check(seed_number());
  verb->add_option("--imaging", *imaging,
                   "How the images are made: realistic (real photographs on the surfaces, motion "
                   "blur, defocus, vignetting, automatic exposure, sensor noise) or clean (the "
                   "ray-traced light alone, procedural textures), as simulate --imaging")
      ->capture_default_str()
      ->check(CLI::IsMember({"clean", "realistic"}));
  verb->callback([out, seed, imaging] {
    std::ostringstream motion, tracking;
    motion << "experiment  figure           paper       simulated   from images:            "
              "outlier tracks\n"
           << "                                         tracks      online      batch       "
              "found/true\n";
    tracking << "tracking    frames  tracks  median    median    95th pct  mistracked  "
                "reacquired (wrong)  ms per frame\n"
             << "                            length    error against the truth   (> 1 px)\n";
    io::write_folder_atomically(*out, [&](const std::string& root) {
      for (const PaperFigures& paper : kPaper) {
        const ExperimentRows rows = run_experiment(paper, *seed, *imaging, root);
        motion << rows.motion;
        tracking << rows.tracking;
      }
      std::ofstream(fs::path(root) / "summary.txt") << motion.str() << "\n" << tracking.str();
    });
    std::cout << motion.str() << "\n"
              << tracking.str() << "Wrote " << *out
              << "/: per experiment the dataset with its rendered images, the tracks from them "
                 "(track/), and the shape-from-motion results on those tracks (sfm/, with "
                 "motion.png, path.png, residuals.png and residuals_per_frame.png).\n";
  });
}

}  // namespace omnisfm::app
