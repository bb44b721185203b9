#include "omnisfm/eval/truth_comparison.h"

#include <cstdio>

#include "omnisfm/io/input_error.h"

namespace omnisfm::eval {

std::string figures_line(const std::string& name, const TrajectoryErrors& e) {
  char line[512];
  std::snprintf(line, sizeof line,
                "%-7s translation %.4f m mean (%.3f%% of %.2f m), rotation %.3f deg, yaw %.3f deg, "
                "rotation spread %.3f deg, scale %.4f\n",
                name.c_str(), e.mean_translation_error_m, e.translation_error_percent,
                e.distance_travelled_m, e.mean_rotation_error_deg, e.mean_yaw_error_deg,
                e.rotation_spread_deg, e.alignment.scale);
  return line;
}

TruthComparison compare_with_truth(const sfm::SfmResult& result, bool batch_ran,
                                   const std::vector<io::StampedPose>& truth,
                                   const std::string& truth_file, bool rigid_too) {
  const size_t frames = static_cast<size_t>(result.num_frames);
  if (truth.size() < frames)
    throw io::InputError(truth_file, 0,
                         "has " + std::to_string(truth.size()) + " poses for " +
                             std::to_string(result.num_frames) + " frames");
  TruthComparison comparison;
  if (truth.size() > frames)
    comparison.report = "truth: " + truth_file + " has " + std::to_string(truth.size()) +
                        " poses and the tracks end at frame " + std::to_string(frames - 1) +
                        "; compared over its first " + std::to_string(frames) + "\n";
  for (size_t f = 0; f < frames; ++f) comparison.truth.push_back(truth[f].world_from_cam);
  const auto compare = [&](const std::string& name,
                           const std::vector<Eigen::Isometry3d>& world_from_cam) {
    const TrajectoryErrors similar = trajectory_errors(world_from_cam, comparison.truth, true);
    comparison.report += figures_line(name, similar);
    if (rigid_too)
      comparison.report +=
          figures_line(name + "/rigid", trajectory_errors(world_from_cam, comparison.truth, false));
    comparison.estimates.push_back({name, world_from_cam, similar.alignment});
  };
  compare("online", result.online_world_from_cam);
  if (batch_ran) compare("batch", result.batch.world_from_cam);
  return comparison;
}

}  // namespace omnisfm::eval
