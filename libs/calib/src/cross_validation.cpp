#include "omnisfm/calib/cross_validation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "omnisfm/calib/staged_calibration.h"

namespace omnisfm::calib {

std::vector<int> spread_views(int num_views, int k) {
  if (k <= 0 || k >= num_views) {
    throw std::invalid_argument("cannot hold out " + std::to_string(k) + " of " +
                                std::to_string(num_views) +
                                " views: at least one must stay for the calibration");
  }
  std::vector<int> indices;
  for (int i = 0; i < k; ++i) {
    indices.push_back(static_cast<int>(std::floor((i + 0.5) * num_views / k)));
  }
  return indices;
}

HeldOutResult evaluate_held_out(const camera::CatadioptricCamera& camera,
                                std::vector<CalibrationView> views) {
  initialize_poses(camera, &views);
  camera::CatadioptricCamera fixed = camera;
  CalibrationSettings settings;
  settings.estimate.assign(camera.num_params(), false);
  settings.max_outlier_rounds = 0;
  const CalibrationReport report = calibrate(&fixed, &views, settings);

  HeldOutResult result;
  std::vector<double> sum2(views.size(), 0.0);
  std::vector<int> count(views.size(), 0);
  double total2 = 0;
  for (const ObservationResidual& r : report.residuals) {
    if (!r.residual.allFinite()) {
      ++result.num_unprojectable;
      continue;
    }
    sum2[r.view] += r.residual.squaredNorm();
    ++count[r.view];
    total2 += r.residual.squaredNorm();
    ++result.num_observations;
  }
  for (std::size_t v = 0; v < views.size(); ++v) {
    result.views.push_back(views[v].name);
    result.view_rms_px.push_back(std::sqrt(sum2[v] / std::max(1, 2 * count[v])));
  }
  result.rms_px = std::sqrt(total2 / std::max(1, 2 * result.num_observations));
  result.residuals = report.residuals;
  return result;
}

ViewPartition hold_out_views(const std::vector<CalibrationView>& views, int k) {
  const std::vector<int> chosen = spread_views(static_cast<int>(views.size()), k);
  ViewPartition partition;
  for (int v = 0; v < static_cast<int>(views.size()); ++v) {
    const bool held = std::find(chosen.begin(), chosen.end(), v) != chosen.end();
    (held ? partition.held : partition.kept).push_back(views[v]);
  }
  return partition;
}

CrossValidation cross_validate(const camera::CatadioptricCamera& start,
                               const std::vector<CalibrationView>& views,
                               const StagedSettings& settings, int folds,
                               const std::function<void(int fold)>& fold_done) {
  const int n = static_cast<int>(views.size());
  if (folds < 2 || folds > n)
    throw std::invalid_argument("cannot cross-validate " + std::to_string(n) + " views in " +
                                std::to_string(folds) + " folds: 2 to " + std::to_string(n));
  CrossValidation result;
  double total2 = 0;
  for (int f = 0; f < folds; ++f) {
    std::vector<CalibrationView> kept, held;
    for (int v = 0; v < n; ++v) (v % folds == f ? held : kept).push_back(views[v]);
    CrossValidationFold fold;
    camera::CatadioptricCamera camera = start;
    fold.calibration = calibrate_in_stages(&camera, &kept, settings);
    if (fold.calibration.final.converged) {
      fold.held = evaluate_held_out(camera, held);
      for (const ObservationResidual& r : fold.held.residuals)
        if (r.residual.allFinite()) total2 += r.residual.squaredNorm();
      result.num_observations += fold.held.num_observations;
      result.num_unprojectable += fold.held.num_unprojectable;
    } else {
      ++result.folds_not_converged;
    }
    result.folds.push_back(std::move(fold));
    if (fold_done) fold_done(f);
  }
  result.pooled_rms_px = std::sqrt(total2 / std::max(1, 2 * result.num_observations));
  return result;
}

}  // namespace omnisfm::calib
