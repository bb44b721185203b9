#pragma once
// Pinhole camera with OpenCV's distortion (k1 k2 p1 p2 k3): for p = (x, y, z), z > 0,
//   a = x/z, b = y/z, r2 = a^2 + b^2, radial = 1 + k1 r2 + k2 r2^2 + k3 r2^3,
//   a' = a radial + 2 p1 a b + p2 (r2 + 2 a^2),  b' = b radial + p1 (r2 + 2 b^2) + 2 p2 a b,
//   u = fx a' + cx,  v = fy b' + cy.
// Parameters, in order: fx fy cx cy k1 k2 p1 p2 k3.

#include "omnisfm/camera/inner_camera.h"

namespace omnisfm::camera {

struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
};

class PinholeCamera final : public InnerCamera {
 public:
  explicit PinholeCamera(const PinholeIntrinsics& intrinsics);

  std::unique_ptr<InnerCamera> clone() const override;
  InnerKind kind() const override { return InnerKind::kPinhole; }
  bool is_orthographic() const override { return false; }
  int num_params() const override { return 9; }
  std::vector<std::string> param_names() const override;
  Eigen::VectorXd params() const override;
  bool set_params(const Eigen::VectorXd& params) override;

  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel, Eigen::Matrix<double, 2, 3>* J_p,
               ParamsJacobian* J_params) const override;
  bool unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                 Eigen::Vector3d* direction) const override;

  const PinholeIntrinsics& intrinsics() const { return k_; }

 private:
  PinholeIntrinsics k_;
};

}  // namespace omnisfm::camera
