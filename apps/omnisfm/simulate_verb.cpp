#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "image_threads.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/sim/dataset_writer.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/imaging.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scenario.h"
#include "simulated_rawlog_output.h"
#include "terminal_progress.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {

namespace {

struct SimulateOptions {
  sim::SimulationOptions simulation;
  std::string out;
  bool render = false;
  int samples = 4;
  std::string imaging = "clean";
  bool rawlog = false;
  bool gps = false;
  // Whether --frames, --imaging, --samples and --survey-error were given.
  CLI::Option* frames_option = nullptr;
  CLI::Option* imaging_option = nullptr;
  CLI::Option* samples_option = nullptr;
  CLI::Option* survey_error_option = nullptr;
};

// Options that mean nothing together, refused as usage errors.
void refuse_meaningless_combinations(const SimulateOptions& o) {
  if (o.imaging_option->count() > 0 && !o.render)
    throw CLI::ValidationError("--imaging", "images are made only with --render");
  if (o.samples_option->count() > 0 && !o.render)
    throw CLI::ValidationError("--samples", "images are made only with --render");
  if (o.survey_error_option->count() > 0 && o.simulation.scenario != "lab")
    throw CLI::ValidationError("--survey-error", "only the lab has surveyed targets");
  if (o.frames_option->count() > 0 && o.simulation.scenario != "drive")
    throw CLI::ValidationError("--frames", "only the drive has a length of your choosing");
  if (o.render && o.simulation.scenario == "drive")
    throw CLI::ValidationError("--render", "the drive has no scene to render: its points are "
                                           "made as it goes");
  if (o.rawlog && !can_write_rawlogs())
    throw CLI::ValidationError("--rawlog", "this omnisfm was built without the MRPT plugin "
                                           "(OMNISFM_BUILD_MRPT_PLUGIN=OFF)");
  if (o.gps && !o.rawlog)
    throw CLI::ValidationError("--gps", "GPS fixes go in the rawlog: add --rawlog");
  if (o.gps && o.simulation.scenario != "rover" && o.simulation.scenario != "drive")
    throw CLI::ValidationError("--gps", "only the rover and the drive have an outdoor variant; "
                                        "the lab and the crane are indoors");
}

// The dataset, its images and its rawlog as asked, written into o.out; a line on stderr.
void simulate_and_write(const SimulateOptions& o) {
  io::check_folder_replaceable(o.out);
  sim::Dataset dataset = [&] {
    try {
      return sim::simulate(o.simulation);
    } catch (const std::invalid_argument& e) {
      throw CLI::ValidationError("simulate", e.what());
    }
  }();
  TerminalProgress progress("rendered", "images");
  sim::FrameImageWriter write_image;
  std::unique_ptr<sim::Renderer> renderer;
  std::unique_ptr<sim::Imaging> camera;
  if (o.render) {
    renderer = std::make_unique<sim::Renderer>(dataset.camera, o.samples, renderer_threads());
    camera = std::make_unique<sim::Imaging>(sim::ImagingSettings::named(o.imaging),
                                            renderer.get(), o.simulation.seed);
    const int image_count = static_cast<int>(dataset.world_from_cam.size());
    write_image = [&, image_count](int frame, const std::string& path) {
      sim::write_png(path, camera->record(dataset, frame));
      progress(frame + 1, image_count);
    };
  }
  std::string rawlog_summary;
  const sim::FolderWriter write_rawlog =
      o.rawlog ? simulated_rawlog_writer(dataset, o.simulation.seed, o.render, o.gps,
                                         &rawlog_summary)
               : nullptr;
  sim::write_dataset(dataset, o.out, write_image, write_rawlog);
  std::cerr << "omnisfm: wrote " << o.out << ": " << dataset.scenario << ", "
            << dataset.world_from_cam.size() << " frames, " << dataset.track_points.size()
            << " tracks, " << dataset.observations.size() << " observations, "
            << dataset.outliers.size() << " mistracked"
            << (rawlog_summary.empty() ? "" : "; " + rawlog_summary) << "\n";
}

}  // namespace

void add_simulate_verb(CLI::App& app) {
  auto o = std::make_shared<SimulateOptions>();
  CLI::App* verb = app.add_subcommand(
      "simulate",
      "Simulate one of the paper's experiments, or a rover drive of any length, with ground "
      "truth: camera.ini, tracks.vnl, frames.vnl, ground_truth.tum, points_gt.vnl, "
      "outliers_gt.vnl (and targets.vnl, observations.vnl for the lab)");
  verb->add_option("--scenario", o->simulation.scenario,
                   "lab | crane | rover (the paper's), or drive: the rover's rig along an endless "
                   "S, 3 cm and 0.5 s per frame, about 30 live ground tracks, no outliers")
      ->required()
      ->check(CLI::IsMember({"lab", "crane", "rover", "drive"}));
  o->frames_option =
      verb->add_option("--frames", o->simulation.frames, "With --scenario drive: how many frames")
          ->capture_default_str()
          ->check(whole_number_between(2, 100000000));
  verb->add_option("--out", o->out,
                   "Output folder: made, or replaced whole when an earlier omnisfm run wrote it (a "
                   "folder holding other files, or the inputs, is refused)")
      ->required();
  verb->add_option("--seed", o->simulation.seed,
                   "Random seed (the dataset is deterministic for it)")
      ->capture_default_str()
      ->check(seed_number());
  verb->add_option("--noise", o->simulation.tracking_noise_px,
                   "Gaussian tracking noise, pixels per coordinate")
      ->capture_default_str()
      ->check(number_between(0, 100));
  o->survey_error_option =
      verb->add_option("--survey-error", o->simulation.survey_error_m,
                       "Gaussian error of the lab's target survey, metres per coordinate")
          ->capture_default_str()
          ->check(number_between(0, 1));
  verb->add_option("--width", o->simulation.image_width, "Image width, pixels")
      ->capture_default_str();
  verb->add_option("--height", o->simulation.image_height, "Image height, pixels")
      ->capture_default_str();
  verb->add_flag("--render", o->render,
                 "Also ray-trace the images through the mirror into images/ (PNG)");
  o->samples_option = verb->add_option("--samples", o->samples,
                                       "Samples per pixel when rendering (a square: 1, 4, 9...)")
                          ->capture_default_str()
                          ->check(CLI::IsMember({1, 4, 9, 16, 25}));
  o->imaging_option =
      verb->add_option("--imaging", o->imaging,
                       "With --render: clean (the ray-traced light as it is, procedural "
                       "textures) or realistic (real photographs on the surfaces, motion blur, "
                       "defocus, vignetting, an automatic exposure's gain changes, shot and read "
                       "noise)")
          ->capture_default_str()
          ->check(CLI::IsMember({"clean", "realistic"}));
  verb->add_flag("--rawlog", o->rawlog,
                 "Also write dataset.rawlog for MRPT (load libomnisfm_mrpt_classes.so to read it): "
                 "tracks, the images with --render, wheel odometry that drifts, a biased gyro");
  verb->add_flag("--gps", o->gps,
                 "With --rawlog and the rover or the drive: the outdoor variant, whose rawlog "
                 "also holds GPS fixes (NMEA GGA, 1 Hz, 2 cm RTK noise about 40.4435 N 79.9455 "
                 "W); writes ground_truth_enu.tum and ground_truth_geodetic.vnl too");
  verb->callback([o] {
    refuse_meaningless_combinations(*o);
    simulate_and_write(*o);
  });
}

}  // namespace omnisfm::app
