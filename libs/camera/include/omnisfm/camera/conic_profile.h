#pragma once
// A conic mirror of revolution in sag form, rho the distance from the axis:
//   z(rho) = z0 + c rho^2 / (1 + sqrt(1 - (1 + kappa) c^2 rho^2)),
// c = 1 / (radius of curvature at the apex) > 0 (convex toward the camera), kappa the conic
// constant: < -1 hyperboloid, -1 paraboloid, (-1, 0) prolate ellipsoid, 0 sphere, > 0 oblate.
// Profile parameter s = rho; shape parameters (z0, c, kappa).
// Domain: rho >= 0 and (1 + kappa) c^2 rho^2 < 1.

#include "omnisfm/camera/mirror_profile.h"

namespace omnisfm::camera {

class ConicProfile final : public MirrorProfile {
 public:
  ConicProfile(double z0, double c, double kappa, double rho_min, double rho_max);

  std::unique_ptr<MirrorProfile> clone() const override;
  MirrorKind kind() const override { return MirrorKind::kConic; }
  int num_shape_params() const override { return 3; }
  std::vector<std::string> shape_param_names() const override;
  Eigen::VectorXd shape_params() const override;
  bool set_shape_params(const Eigen::VectorXd& params) override;
  bool set_valid_range(double s_min, double s_max) override;

  void evaluate(double rho, MeridianPoint* point, MeridianShapeJacobian* J_shape) const override;
  double implicit(double rho, double z, double* dG_drho, double* dG_dz) const override;
  double parameter_at(double rho, double z) const override;
  void solve_domain(double* lo, double* hi) const override;

  double z0() const { return z0_; }
  double c() const { return c_; }
  double kappa() const { return kappa_; }
  // The largest rho at which the sag formula is defined (infinity for paraboloids, hyperboloids).
  double rho_domain_max() const;

  // The foci on the axis, for kappa < 0 (ellipsoids, paraboloids, hyperboloids): the one behind
  // the reflective face (inside the mirror) and, except for paraboloids, the one in front of it.
  double inner_focus_z() const;
  double outer_focus_z() const;

 private:
  bool valid_shape(double z0, double c, double kappa, double rho_max) const;
  double z0_, c_, kappa_;
};

}  // namespace omnisfm::camera
