#pragma once
// Calibration from a starting guess a user can write from a datasheet (nominal mirror, lens focal
// length, image centre), which may be far from the truth:
//   1. every view's pose from initial_pose() on the starting camera, no guess needed;
//   2. stages that free the parameter groups one after another (mirror-pose, then intrinsics,
//      then mirror-shape, then distortion, each only as far as asked for), with the mirror's
//      valid range widened, so that a point whose reflection strays past the rim on the way does
//      not stop the solve, and a Cauchy loss, against a few grossly wrong detections;
//   3. the final solve of everything asked for, with squared residuals, the camera's own valid
//      range, outlier rejection and the covariance: calibrate() as it is.
// Parameters the others make unobservable are held (parameter_gauge.h): without that, a solve of
// every group wanders and does not converge. With it, one solve from a datasheet guess mostly
// converges too; the stages are the safeguard (20 of 20 synthetic board sets against 19 of 20).
// When only one group is asked for, the early stages are skipped: the paper's mirror-pose
// calibration is step 1 then step 3.

#include <functional>
#include <string>
#include <vector>

#include "omnisfm/calib/calibration_problem.h"
#include "omnisfm/calib/parameter_gauge.h"

namespace omnisfm::calib {

struct StagedSettings {
  // Parameter groups to estimate, as estimate_mask() takes them.
  std::vector<std::string> groups = {"mirror-pose"};
  double outlier_threshold_sigma = 4.0;
  int max_outlier_rounds = 5;
  int max_iterations = 200;
  // Cauchy scale of the early stages, pixels.
  double early_cauchy_scale_px = 2.0;
  // Called as the solver iterates: the stage's name, the iteration, the RMS so far (pixels).
  std::function<void(const std::string& stage, int iteration, double rms_px)> progress;
};

struct StageSummary {
  std::string name;   // e.g. "mirror-pose+intrinsics"
  int iterations = 0;
  double rms_px = 0;  // per coordinate, over the observations the stage used
  bool converged = false;
};

struct StagedReport {
  CalibrationReport final;                 // the last solve, as calibrate() reports it
  std::vector<StageSummary> stages;        // the early stages, then the final one
  std::vector<HeldParameter> held;         // asked for but held at the starting value
  std::vector<std::string> estimated;      // names of the parameters estimated
  std::vector<bool> estimate_mask;         // the same as a mask over params()
};

// Solves for the views' poses (initialised here, whatever they held) and the camera parameters
// named by settings.groups, less the unobservable ones. Throws std::invalid_argument naming the
// view when a view's pose cannot be initialised (fewer than 6 of its points reflect in the
// starting camera, or no consistent pose), and for an unknown group or too few observations.
// A solve that does not converge is reported, not thrown.
StagedReport calibrate_in_stages(camera::CatadioptricCamera* camera,
                                 std::vector<CalibrationView>* views,
                                 const StagedSettings& settings);

// Sets every view's pose from initial_pose() on the camera. Throws std::invalid_argument naming the
// first view whose pose cannot be initialised.
void initialize_poses(const camera::CatadioptricCamera& camera,
                      std::vector<CalibrationView>* views);

}  // namespace omnisfm::calib
