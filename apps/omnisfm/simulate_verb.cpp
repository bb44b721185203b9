#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "omnisfm/io/input_error.h"
#include "omnisfm/sim/dataset_writer.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/imaging.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scenario.h"
#include "simulated_rawlog_output.h"
#include "verb_inputs.h"
#include "terminal_progress.h"
#include "verbs.h"

namespace omnisfm::app {

void add_simulate_verb(CLI::App& app) {
  auto options = std::make_shared<sim::SimulationOptions>();
  auto out = std::make_shared<std::string>();
  auto render = std::make_shared<bool>(false);
  auto samples = std::make_shared<int>(4);
  auto imaging = std::make_shared<std::string>("clean");
  auto rawlog = std::make_shared<bool>(false);
  auto gps = std::make_shared<bool>(false);
  CLI::App* verb = app.add_subcommand(
      "simulate",
      "Simulate one of the paper's experiments, or a rover drive of any length, with ground "
      "truth: camera.ini, tracks.vnl, frames.vnl, ground_truth.tum, points_gt.vnl, "
      "outliers_gt.vnl (and targets.vnl, observations.vnl for the lab)");
  verb->add_option("--scenario", options->scenario,
                   "lab | crane | rover (the paper's), or drive: the rover's rig along an endless "
                   "S, 3 cm and 0.5 s per frame, about 30 live ground tracks, no outliers")
      ->required()
      ->check(CLI::IsMember({"lab", "crane", "rover", "drive"}));
  CLI::Option* frames =
      verb->add_option("--frames", options->frames, "With --scenario drive: how many frames")
          ->capture_default_str()
          ->check(whole_number_between(2, 100000000));
  verb->add_option("--out", *out, "Output folder (replaced whole when it exists)")->required();
  verb->add_option("--seed", options->seed, "Random seed (the dataset is deterministic for it)")
      ->capture_default_str();
  verb->add_option("--noise", options->tracking_noise_px,
                   "Gaussian tracking noise, pixels per coordinate")
      ->capture_default_str()
      ->check(number_between(0, 100));
  verb->add_option("--survey-error", options->survey_error_m,
                   "Gaussian error of the lab's target survey, metres per coordinate")
      ->capture_default_str()
      ->check(number_between(0, 1));
  verb->add_option("--width", options->image_width, "Image width, pixels")->capture_default_str();
  verb->add_option("--height", options->image_height, "Image height, pixels")
      ->capture_default_str();
  verb->add_flag("--render", *render,
                 "Also ray-trace the images through the mirror into images/ (PNG)");
  verb->add_option("--samples", *samples, "Samples per pixel when rendering (a square: 1, 4, 9...)")
      ->capture_default_str()
      ->check(CLI::IsMember({1, 4, 9, 16, 25}));
  CLI::Option* imaging_option = verb->add_option("--imaging", *imaging,
                   "With --render: clean (the ray-traced light as it is, procedural textures) or "
                   "realistic (real photographs on the surfaces, motion blur, defocus, vignetting, "
                   "an automatic exposure's gain changes, shot and read noise)")
      ->capture_default_str()
      ->check(CLI::IsMember({"clean", "realistic"}));
  verb->add_flag("--rawlog", *rawlog,
                 "Also write dataset.rawlog for MRPT (load libomnisfm_mrpt_classes.so to read it): "
                 "tracks, the images with --render, wheel odometry that drifts, a biased gyro");
  verb->add_flag("--gps", *gps,
                 "With --rawlog and the rover or the drive: the outdoor variant, whose rawlog also holds GPS "
                 "fixes (NMEA GGA, 1 Hz, 2 cm RTK noise about 40.4435 N 79.9455 W); writes "
                 "ground_truth_enu.tum and ground_truth_geodetic.vnl too");
  verb->callback([options, out, render, samples, imaging, imaging_option, rawlog, gps, frames] {
    if (imaging_option->count() > 0 && !*render)
      throw CLI::ValidationError("--imaging", "images are made only with --render");
    if (frames->count() > 0 && options->scenario != "drive")
      throw CLI::ValidationError("--frames", "only the drive has a length of your choosing");
    if (*render && options->scenario == "drive")
      throw CLI::ValidationError("--render", "the drive has no scene to render: its points are "
                                             "made as it goes");
    if (*rawlog && !can_write_rawlogs())
      throw CLI::ValidationError("--rawlog", "this omnisfm was built without the MRPT plugin "
                                             "(OMNISFM_BUILD_MRPT_PLUGIN=OFF)");
    if (*gps && !*rawlog)
      throw CLI::ValidationError("--gps", "GPS fixes go in the rawlog: add --rawlog");
    if (*gps && options->scenario != "rover" && options->scenario != "drive")
      throw CLI::ValidationError("--gps", "only the rover and the drive have an outdoor variant; "
                                          "the lab and the crane are indoors");
    sim::Dataset dataset = [&] {
      try {
        return sim::simulate(*options);
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("simulate", e.what());
      }
    }();
    require_writable_folder_of(*out);
    TerminalProgress progress("rendered", "images");
    sim::FrameImageWriter write_image;
    std::unique_ptr<sim::Renderer> renderer;
    std::unique_ptr<sim::Imaging> camera;
    if (*render) {
      renderer = std::make_unique<sim::Renderer>(dataset.camera, *samples);
      camera = std::make_unique<sim::Imaging>(sim::ImagingSettings::named(*imaging),
                                              renderer.get(), options->seed);
      const int image_count = static_cast<int>(dataset.world_from_cam.size());
      write_image = [&, image_count](int frame, const std::string& path) {
        sim::write_png(path, camera->record(dataset, frame));
        progress(frame + 1, image_count);
      };
    }
    std::string rawlog_summary;
    const sim::FolderWriter write_rawlog =
        *rawlog ? simulated_rawlog_writer(dataset, options->seed, *render, *gps, &rawlog_summary)
                : nullptr;
    sim::write_dataset(dataset, *out, write_image, write_rawlog);
    std::cerr << "omnisfm: wrote " << *out << ": " << dataset.scenario << ", "
              << dataset.world_from_cam.size() << " frames, " << dataset.track_points.size()
              << " tracks, " << dataset.observations.size() << " observations, "
              << dataset.outliers.size() << " mistracked"
              << (rawlog_summary.empty() ? "" : "; " + rawlog_summary) << "\n";
  });
}

}  // namespace omnisfm::app
