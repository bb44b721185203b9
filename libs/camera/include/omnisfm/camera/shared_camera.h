#pragma once
// The camera a Ceres problem's residuals project with when its parameters are a block of the
// problem: moved to the block's values once per evaluation point (a ceres::EvaluationCallback:
// Problem::Options::evaluation_callback), rather than once per residual. Ceres calls it before
// every solver evaluation and every Problem::Evaluate, so the residuals, the covariances and any
// later evaluation see the parameters they are asked at.

#include <ceres/evaluation_callback.h>

#include <Eigen/Core>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::camera {

class SharedCamera : public ceres::EvaluationCallback {
 public:
  // `params`: the problem's block of camera.num_params() values, which outlives this.
  SharedCamera(const CatadioptricCamera& camera, double* params)
      : camera_(camera), params_(params), size_(camera.num_params()) {}
  void PrepareForEvaluation(bool, bool new_point) override {
    if (new_point) valid_ = camera_.set_params(Eigen::Map<const Eigen::VectorXd>(params_, size_));
  }
  const CatadioptricCamera& camera() const { return camera_; }
  // False where the camera refused the block's values: every residual then fails.
  bool valid() const { return valid_; }

 private:
  CatadioptricCamera camera_;
  double* params_;
  int size_;
  bool valid_ = true;
};

}  // namespace omnisfm::camera
