#pragma once
// Residuals a batch problem can carry beyond the reprojections (the vehicle's motion sensors), and
// the batch adjustment that takes them.

#include <ceres/ceres.h>

#include <utility>
#include <vector>

#include "omnisfm/core/pose_vector.h"
#include "omnisfm/sfm/batch_adjustment.h"

namespace omnisfm::sfm {

// cam_from_world as (angle-axis, translation): the batch's pose parameter block.
using core::PoseVector;

class ExtraTerms {
 public:
  virtual ~ExtraTerms() = default;
  // Adds the residuals on the poses (one per frame) and on parameter blocks of its own, which
  // must outlive the solve. Returns true when they fix the gauge themselves (absolute positions),
  // so that no pose is held fixed.
  virtual bool add(ceres::Problem* problem, std::vector<PoseVector>* poses) = 0;
  // After add: whether its residuals fix the scene's scale (distances travelled, positions).
  // When they do not (a gyro alone), the batch finds and holds the scale as without them.
  virtual bool fixes_scale() const = 0;
  // Its own blocks whose covariance the batch computes with the poses' and points' (when asked
  // for), and hands back through take_covariance, scaled as theirs.
  virtual std::vector<std::pair<double*, int>> blocks_with_covariance() { return {}; }
  virtual void take_covariance(const double* /*block*/, const Eigen::MatrixXd& /*covariance*/) {}
};

// As the public batch_adjust, started from the poses as its parameters hold them (the pipeline
// passes the filter's own, unchanged by a round trip through world_from_cam), with `extra` (when
// not null) added to the problem. Points are then always the eliminated group, as the extra
// residuals tie poses together.
BatchResult batch_adjust_with_terms(const camera::CatadioptricCamera& camera,
                                    const std::vector<core::TrackObservation>& observations,
                                    const std::vector<Eigen::Isometry3d>& start_cam_from_world,
                                    const std::map<int, Eigen::Vector3d>& points,
                                    const BatchSettings& settings, ExtraTerms* extra);

}  // namespace omnisfm::sfm
