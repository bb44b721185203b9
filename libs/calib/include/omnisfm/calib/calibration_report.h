#pragma once
// What a calibration reports, mrcal-style, as a folder beside the calibrated camera file:
//   report.txt       status, stages, RMS and worst residual, per-view RMS, outliers, parameters
//                    with their 1-sigma, held-out views, cross-validation, projection
//                    uncertainty
//   residuals.vnl    `# view name point x y du dv outlier`: every observation, observed pixel
//                    (x, y) and residual (du, dv) = projected - observed
//   residuals.png    the residual vectors drawn over the image (y down), scaled, the scale stated
//   histogram.png    the residual coordinates' histogram with the normal curve of the RMS
//   uncertainty.vnl  `# x y sigma`: the projection-uncertainty map, uncertainty.png its heat map
// The .gp gnuplot scripts that draw the PNGs stay beside them, so that plots can be redrawn.

#include <optional>
#include <string>
#include <vector>

#include "omnisfm/calib/cross_validation.h"
#include "omnisfm/calib/projection_uncertainty.h"
#include "omnisfm/calib/staged_calibration.h"

namespace omnisfm::calib {

struct CalibrationOutcome {
  std::vector<std::string> inputs;  // "camera INITIAL.ini", "corners corners.vnl", ...
  std::string camera_file;          // where the calibrated camera went ("" when not written)
  const camera::CatadioptricCamera* camera = nullptr;  // calibrated
  const StagedReport* report = nullptr;
  const std::vector<CalibrationView>* views = nullptr;  // with their solved poses
  const HeldOutResult* held_out = nullptr;              // may be null
  const CrossValidation* cross_validation = nullptr;    // may be null
  const UncertaintyMap* uncertainty = nullptr;          // may be null; the one plotted
  const UncertaintyMap* uncertainty_camera_frame = nullptr;  // may be null; in the text only
  double outlier_threshold_sigma = 4;                   // as the calibration used it
};

// The text of report.txt.
std::string report_text(const CalibrationOutcome& outcome);

// Writes the folder (created when absent, files replaced). The PNGs are drawn by gnuplot; when
// it cannot run, they are left out and the returned note says so (empty otherwise). Throws
// std::runtime_error naming the file when one cannot be written.
std::string write_calibration_report(const std::string& folder, const CalibrationOutcome& outcome);

}  // namespace omnisfm::calib
