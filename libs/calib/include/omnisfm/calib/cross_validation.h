#pragma once
// Cross-validation: views left out of a calibration, then measured against it. The held-out
// views' poses are solved with the calibrated camera fixed (from initial_pose(), then refined), and
// their residuals counted in full, with no outlier rejection, so that a model with too many
// parameters cannot look better than it is.

#include <string>
#include <vector>

#include "omnisfm/calib/calibration_problem.h"

namespace omnisfm::calib {

// k of num_views views, spread evenly: indices round((i + 0.5) * num_views / k), increasing.
// Throws std::invalid_argument unless 0 < k < num_views.
std::vector<int> spread_views(int num_views, int k);

struct HeldOutResult {
  std::vector<std::string> views;
  std::vector<double> view_rms_px;  // per coordinate, all observations of the view
  double rms_px = 0;                // per coordinate, over all held-out observations
  int num_observations = 0;
  int num_unprojectable = 0;        // observations the camera cannot project at the solved pose
  std::vector<ObservationResidual> residuals;
};

// Throws std::invalid_argument naming a view whose pose cannot be initialised.
HeldOutResult evaluate_held_out(const camera::CatadioptricCamera& camera,
                                std::vector<CalibrationView> views);

}  // namespace omnisfm::calib
