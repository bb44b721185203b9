#pragma once
// Orthographic (telecentric) camera, for para-catadioptric rigs: every pixel looks along +z.
//   u = fx x + cx,  v = fy y + cy,
// fx, fy in pixels per metre. Parameters, in order: fx fy cx cy.

#include "omnisfm/camera/inner_camera.h"

namespace omnisfm::camera {

struct OrthographicIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

class OrthographicCamera final : public InnerCamera {
 public:
  explicit OrthographicCamera(const OrthographicIntrinsics& intrinsics);

  std::unique_ptr<InnerCamera> clone() const override;
  InnerKind kind() const override { return InnerKind::kOrthographic; }
  bool is_orthographic() const override { return true; }
  int num_params() const override { return 4; }
  std::vector<std::string> param_names() const override;
  Eigen::VectorXd params() const override;
  bool set_params(const Eigen::VectorXd& params) override;

  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel, Eigen::Matrix<double, 2, 3>* J_p,
               ParamsJacobian* J_params) const override;
  bool unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                 Eigen::Vector3d* direction) const override;

  const OrthographicIntrinsics& intrinsics() const { return k_; }

 private:
  OrthographicIntrinsics k_;
};

}  // namespace omnisfm::camera
