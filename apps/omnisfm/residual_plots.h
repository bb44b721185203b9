#pragma once
// Residual plots of a shape-from-motion estimate (PNG via gnuplot): the reprojection residual
// vectors drawn over the image, outlier tracks apart, and the residuals' spread per frame, where
// a bad stretch of the sequence shows at a glance.

#include <string>
#include <vector>

#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sfm/reprojection_residuals.h"

namespace omnisfm::app {

// Writes residuals.vnl (`# frame track x y du dv outlier`), residuals.png and
// residuals_per_frame.png (with their .gp scripts) into the existing folder `dir`. Returns false
// when gnuplot is missing or failed; residuals.vnl is written either way.
bool write_residual_plots(const std::string& dir, int image_width, int image_height,
                          const std::vector<sfm::ObservationResidual>& residuals);

// The same for a pipeline's result on `tracks`: the batch's estimate when it ran, else the
// filter's; outlier tracks apart, where an estimate of their point exists.
bool write_residual_plots(const std::string& dir, const camera::CatadioptricCamera& camera,
                          const std::vector<core::TrackObservation>& tracks,
                          const sfm::SfmResult& result, bool batch_ran);

}  // namespace omnisfm::app
