#include "omnisfm/calib/cross_validation.h"

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

}  // namespace omnisfm::calib
