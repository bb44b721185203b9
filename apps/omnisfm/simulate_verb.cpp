#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include "omnisfm/io/input_error.h"
#include "omnisfm/sim/dataset_writer.h"
#include "omnisfm/sim/scenario.h"
#include "verbs.h"

namespace omnisfm::app {

void add_simulate_verb(CLI::App& app) {
  auto options = std::make_shared<sim::SimulationOptions>();
  auto out = std::make_shared<std::string>();
  CLI::App* verb = app.add_subcommand(
      "simulate",
      "Simulate one of the paper's experiments with ground truth: camera.ini, tracks.vnl, "
      "frames.vnl, ground_truth.tum, points_gt.vnl, outliers_gt.vnl (and targets.vnl, "
      "observations.vnl for the lab)");
  verb->add_option("--scenario", options->scenario, "lab | crane | rover")
      ->required()
      ->check(CLI::IsMember({"lab", "crane", "rover"}));
  verb->add_option("--out", *out, "Output folder (replaced whole when it exists)")->required();
  verb->add_option("--seed", options->seed, "Random seed (the dataset is deterministic for it)")
      ->capture_default_str();
  verb->add_option("--noise", options->tracking_noise_px,
                   "Gaussian tracking noise, pixels per coordinate")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  verb->add_option("--survey-error", options->survey_error_m,
                   "Gaussian error of the lab's target survey, metres per coordinate")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  verb->add_option("--width", options->image_width, "Image width, pixels")->capture_default_str();
  verb->add_option("--height", options->image_height, "Image height, pixels")
      ->capture_default_str();
  verb->callback([options, out] {
    sim::Dataset dataset = [&] {
      try {
        return sim::simulate(*options);
      } catch (const std::invalid_argument& e) {
        throw CLI::ValidationError("simulate", e.what());
      }
    }();
    const std::filesystem::path parent =
        std::filesystem::absolute(*out).lexically_normal().parent_path();
    if (!std::filesystem::is_directory(parent) || ::access(parent.c_str(), W_OK) != 0)
      throw io::InputError(*out, 0, "cannot write here: " + parent.string() +
                                        " is not a writable folder");
    sim::write_dataset(dataset, *out);
    std::cerr << "omnisfm: wrote " << *out << ": " << dataset.scenario << ", "
              << dataset.world_from_cam.size() << " frames, " << dataset.track_points.size()
              << " tracks, " << dataset.observations.size() << " observations, "
              << dataset.outliers.size() << " mistracked\n";
  });
}

}  // namespace omnisfm::app
