#include "omnisfm/calib/staged_calibration.h"

#include <stdexcept>

#include "omnisfm/calib/pose_initialization.h"

namespace omnisfm::calib {
namespace {

// The camera with its mirror's valid range stretched as far as the profile allows (up to twice
// the given range beyond the rim, and down to the axis): early stages evaluate the analytic
// continuation of the mirror instead of rejecting every step that moves a point past the rim.
camera::CatadioptricCamera with_widened_range(const camera::CatadioptricCamera& camera) {
  std::unique_ptr<camera::MirrorProfile> mirror = camera.mirror().clone();
  const double lo = mirror->s_min(), hi = mirror->s_max();
  for (double stretch = 2.0; stretch > 0.01; stretch *= 0.5) {
    if (mirror->set_valid_range(0, hi + stretch * (hi - lo))) break;
  }
  return camera::CatadioptricCamera(camera.inner().clone(), std::move(mirror),
                                    camera.mirror_pose(), camera.image_width(),
                                    camera.image_height());
}

std::string joined(const std::vector<std::string>& parts) {
  std::string text;
  for (const std::string& part : parts) text += (text.empty() ? "" : "+") + part;
  return text;
}

}  // namespace

void initialize_poses(const camera::CatadioptricCamera& camera,
                      std::vector<CalibrationView>* views) {
  for (CalibrationView& view : *views) {
    if (!initial_pose(camera, view.points, view.pixels, &view.cam_from_object)) {
      throw std::invalid_argument(
          view.name + ": no pose found for its " + std::to_string(view.points.size()) +
          " observations (at least 6 must reflect in the starting camera, consistently)");
    }
  }
}

StagedReport calibrate_in_stages(camera::CatadioptricCamera* camera,
                                 std::vector<CalibrationView>* views,
                                 const StagedSettings& settings) {
  StagedReport result;
  result.estimate_mask = estimate_mask(*camera, settings.groups);
  result.held = hold_unobservable_parameters(*camera, &result.estimate_mask);
  const std::vector<std::string> names = camera->param_names();
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (result.estimate_mask[i]) result.estimated.push_back(names[i]);
  }
  initialize_poses(*camera, views);

  // Early stages: the groups asked for, freed in a fixed order.
  const std::vector<std::string> order = {"mirror-pose", "intrinsics", "mirror-shape",
                                          "distortion"};
  std::vector<std::string> freed;
  std::vector<bool> previous(result.estimate_mask.size(), false);
  camera::CatadioptricCamera widened = with_widened_range(*camera);
  for (const std::string& group : order) {
    freed.push_back(group);
    std::vector<bool> mask = estimate_mask(*camera, freed);
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = mask[i] && result.estimate_mask[i];
    if (mask == previous || mask == result.estimate_mask) continue;
    previous = mask;
    CalibrationSettings stage;
    stage.estimate = mask;
    stage.max_outlier_rounds = 0;
    stage.max_iterations = settings.max_iterations;
    stage.cauchy_scale_px = settings.early_cauchy_scale_px;
    const std::string name = joined(freed);
    if (settings.progress) {
      stage.progress = [&](int iteration, double rms) { settings.progress(name, iteration, rms); };
    }
    const CalibrationReport report = calibrate(&widened, views, stage);
    result.stages.push_back({name, report.iterations, report.rms_px, report.converged});
  }
  // The widened range only loosened the profile's domain: the values fit the camera's own.
  if (!camera->set_params(widened.params()))
    throw std::logic_error("calibrate_in_stages: the early stages left the camera's domain");

  CalibrationSettings final_stage;
  final_stage.estimate = result.estimate_mask;
  final_stage.outlier_threshold_sigma = settings.outlier_threshold_sigma;
  final_stage.max_outlier_rounds = settings.max_outlier_rounds;
  final_stage.max_iterations = settings.max_iterations;
  if (settings.progress) {
    final_stage.progress = [&](int iteration, double rms) {
      settings.progress("final", iteration, rms);
    };
  }
  result.final = calibrate(camera, views, final_stage);
  result.stages.push_back(
      {"final", result.final.iterations, result.final.rms_px, result.final.converged});
  return result;
}

}  // namespace omnisfm::calib
