// omnisfm eval: the paper's error figures of an estimated trajectory against the truth.

#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "omnisfm/eval/timestamp_pairing.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/tum_trajectory.h"
#include "sfm_outputs.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {

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
    const eval::PairedPoses paired = eval::pair_by_timestamp(estimate, truth);
    if (paired.estimate.size() < 3) {
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
    eval::TrajectoryErrors e;
    try {
      e = eval::trajectory_errors(paired.estimate, paired.truth, !o->rigid);
    } catch (const std::invalid_argument&) {
      // Horn's alignment of the positions leaves the rotation about their line free.
      throw io::InputError(o->estimate, 0,
                           "its " + std::to_string(paired.estimate.size()) +
                               " positions paired with " + o->ground_truth +
                               "'s lie on one line or coincide: no alignment of the positions "
                               "fixes the rotation about it");
    }
    std::cout << "poses " << paired.estimate.size() << "\n"
              << eval::figures_line(o->rigid ? "rigid" : "similar", e);
    finish_stdout();
  });
}

}  // namespace omnisfm::app
