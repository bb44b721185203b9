// The main job, end to end on the embedded default: the paper's three experiments simulated (the
// lab's images rendered through the mirror), shape-from-motion on their tracks, and the paper's
// error figures next to the paper's own, with the x-y paths plotted.

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>

#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/dataset_writer.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scenario.h"
#include "output_folder.h"
#include "sfm_outputs.h"
#include "trajectory_plots.h"
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

}  // namespace

void add_demo_verb(CLI::App& app) {
  auto out = std::make_shared<std::string>("out");
  auto seed = std::make_shared<std::uint64_t>(1);
  CLI::App* verb = app.add_subcommand(
      "demo",
      "The main job: the paper's lab, crane and rover experiments simulated (the lab rendered "
      "through the mirror), shape-from-motion on them, and the error figures next to the paper's");
  verb->add_option("--out", *out, "Output folder (replaced whole when it exists)")
      ->capture_default_str();
  verb->add_option("--seed", *seed, "Random seed of the simulations")->capture_default_str();
  verb->callback([out, seed] {
    const bool terminal = ::isatty(STDERR_FILENO);
    std::ostringstream table;
    table << "experiment  figure           paper       online      batch       outliers found/true\n";
    write_folder(*out, [&](const std::string& root) {
      for (const PaperFigures& paper : kPaper) {
        sim::SimulationOptions options;
        options.scenario = paper.scenario;
        options.seed = *seed;
        const sim::Dataset d = sim::simulate(options);
        const fs::path dir = fs::path(root) / paper.scenario;
        fs::create_directories(dir);
        sim::FrameImageWriter images;
        std::unique_ptr<sim::Renderer> renderer;
        if (paper.scenario == std::string("lab")) {
          if (terminal) std::cerr << "omnisfm: rendering the lab through the mirror\n";
          renderer = std::make_unique<sim::Renderer>(d.camera, 4);
          images = [&](int frame, const std::string& path) {
            sim::write_png(path, renderer->render(d.scene, d.world_from_cam[frame]));
          };
        }
        sim::write_dataset(d, (dir / "dataset").string(), images);

        const std::vector<io::TrackObservation>& tracks = d.observations;
        sfm::SfmSettings settings;
        settings.batch.covariances = false;
        const sfm::SfmResult r = sfm::run_sfm(d.camera, tracks, settings, [&](int done, int all) {
          if (terminal && (done % 10 == 0 || done == all))
            std::cerr << "\romnisfm: " << paper.scenario << ": filter " << done << "/" << all
                      << (done == all ? "\n" : "") << std::flush;
        });
        const auto online = eval::trajectory_errors(world_from_cam(r.online_cam_from_world),
                                                    d.world_from_cam, true);
        const auto batch = eval::trajectory_errors(world_from_cam(r.batch.cam_from_world),
                                                   d.world_from_cam, true);
        std::set<int> found, truth;
        for (const auto& o : r.outliers) found.insert(o.track);
        for (const auto& o : d.outliers) truth.insert(o.track);
        const auto outliers = eval::outlier_detection(found, truth);

        std::ostringstream report;
        report << figures_line("online", online) << figures_line("batch", batch);
        fs::create_directories(dir / "sfm");
        write_sfm_outputs((dir / "sfm").string(), r, true, d.timestamps, report.str());
        const bool plotted = write_trajectory_plots(
            (dir / "sfm").string(), d.world_from_cam,
            {{"online", world_from_cam(r.online_cam_from_world), online.alignment},
             {"batch", world_from_cam(r.batch.cam_from_world), batch.alignment}});

        char line[256];
        std::snprintf(line, sizeof line, "%-11s translation      %6.2f %%    %6.3f %%    %6.3f %%    %d/%d\n",
                      paper.scenario, paper.translation_percent, online.translation_error_percent,
                      batch.translation_error_percent, outliers.correct, outliers.actual);
        table << line;
        std::snprintf(line, sizeof line, "%-11s %-16s %6.2f deg  %6.3f deg  %6.3f deg%s\n", "",
                      paper.rotation_kind, paper.rotation_deg,
                      rotation_figure(paper.rotation_kind, online),
                      rotation_figure(paper.rotation_kind, batch),
                      plotted ? "" : "   (no gnuplot: path.png not drawn)");
        table << line;
      }
      std::ofstream(fs::path(root) / "summary.txt") << table.str();
    });
    std::cout << table.str() << "Wrote " << *out
              << "/: per experiment the dataset (the lab with rendered images), the sfm results "
                 "and sfm/motion.png, sfm/path.png.\n";
  });
}

}  // namespace omnisfm::app
