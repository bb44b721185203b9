#pragma once
// Cross-validation: views left out of a calibration, then measured against it. The held-out
// views' poses are solved with the calibrated camera fixed (from initial_pose(), then refined), and
// their residuals counted in full, with no outlier rejection, so that a model with too many
// parameters cannot look better than it is. K-fold cross-validation, as mrcal users compare
// models, holds out every view once.

#include <functional>
#include <string>
#include <vector>

#include "omnisfm/calib/calibration_problem.h"
#include "omnisfm/calib/staged_calibration.h"

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

// The views a calibration uses and those it leaves out: spread_views(views.size(), k), in order.
struct ViewPartition {
  std::vector<CalibrationView> kept, held;
};
ViewPartition hold_out_views(const std::vector<CalibrationView>& views, int k);

struct CrossValidationFold {
  StagedReport calibration;  // of the views kept
  HeldOutResult held;        // empty when the calibration did not converge
};

struct CrossValidation {
  std::vector<CrossValidationFold> folds;
  // Per coordinate, over every held-out observation of the folds whose calibration converged.
  double pooled_rms_px = 0;
  int num_observations = 0;
  int num_unprojectable = 0;
  int folds_not_converged = 0;
};

// Fold f holds out the views v with v % folds == f (each fold spans the sequence), calibrates the
// others from `start` as calibrate_in_stages() does with `settings`, and measures the views held
// out against that camera. `fold_done(f)` is called after each fold, when given. Throws
// std::invalid_argument unless 2 <= folds <= views.size(), or naming a view that cannot be posed.
CrossValidation cross_validate(const camera::CatadioptricCamera& start,
                               const std::vector<CalibrationView>& views,
                               const StagedSettings& settings, int folds,
                               const std::function<void(int fold)>& fold_done = {});

}  // namespace omnisfm::calib
