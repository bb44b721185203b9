#pragma once
// What the sfm verb (and the demo) write for a shape-from-motion result.

#include <string>
#include <vector>

#include "omnisfm/eval/truth_comparison.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/sfm/pipeline.h"
#include "trajectory_plots.h"

namespace omnisfm::app {

// online.tum, batch.tum (when the batch ran), points.vnl, points.ply, outliers.vnl and
// report.txt (with `report`) into the existing folder `dir`.
void write_sfm_outputs(const std::string& dir, const sfm::SfmResult& result, bool batch_ran,
                       const std::vector<double>& frame_times, const std::string& report);

// With the camera refined by the batch (BatchResult::camera_refined), DIR/camera_refined.ini:
// `camera` at the batch's parameters, with the batch's covariance of the refined ones when it
// has one. Nothing otherwise.
void write_refined_camera(const std::string& dir, const camera::CatadioptricCamera& camera,
                          const sfm::BatchResult& batch, const sfm::BatchSettings& settings);

// For a streamed run: DIR/online.tum read back (the comparison needs the whole estimate) and
// compared with the truth as eval::compare_with_truth does; its figures appended to DIR/report.txt and
// returned, its trajectory plots written into DIR.
std::string compare_written_online_with_truth(const std::string& dir,
                                              const std::vector<io::StampedPose>& truth,
                                              const std::string& truth_file, bool rigid_too);

// The residual plots of `result` on `tracks`, and the trajectory plots of `comparison` when it
// has any, into `dir`; says on stderr when gnuplot could not draw them.
void write_sfm_plots(const std::string& dir, const camera::CatadioptricCamera& camera,
                     const std::vector<core::TrackObservation>& tracks,
                     const sfm::SfmResult& result, bool batch_ran,
                     const eval::TruthComparison& comparison);

}  // namespace omnisfm::app
