#pragma once
// The equiangular mirror of Chahl and Srinivasan, in polar form about the frame origin:
//   r(theta) = r0 * cos(k theta)^(-1/k),   k = (1 + alpha) / 2,
//   m(theta, phi) = r(theta) (sin theta cos phi, sin theta sin phi, cos theta),
// theta the angle from +z. With a pinhole at the origin, a camera ray at angle theta leaves the
// mirror at alpha * theta from -z. Profile parameter s = theta; shape parameters (alpha, r0).
// Domain: 0 <= theta < pi / (2k).

#include "omnisfm/camera/mirror_profile.h"

namespace omnisfm::camera {

class EquiangularProfile final : public MirrorProfile {
 public:
  // theta_min: edge of the camera's own reflection; theta_max: the rim.
  EquiangularProfile(double alpha, double r0, double theta_min, double theta_max);

  std::unique_ptr<MirrorProfile> clone() const override;
  MirrorKind kind() const override { return MirrorKind::kEquiangular; }
  int num_shape_params() const override { return 2; }
  std::vector<std::string> shape_param_names() const override;
  Eigen::VectorXd shape_params() const override;
  bool set_shape_params(const Eigen::VectorXd& params) override;
  bool set_valid_range(double s_min, double s_max) override;

  void evaluate(double theta, MeridianPoint* point, MeridianShapeJacobian* J_shape) const override;
  double implicit(double rho, double z, double* dG_drho, double* dG_dz) const override;
  double parameter_at(double rho, double z) const override;
  void solve_domain(double* lo, double* hi) const override;

  double alpha() const { return alpha_; }
  double r0() const { return r0_; }
  // The polar radius r(theta).
  double radius(double theta) const;

  static bool valid_shape(double alpha, double r0);

 private:
  double alpha_, r0_;
};

}  // namespace omnisfm::camera
