#pragma once
// A tabulated mirror profile: samples (rho_i, z_i) of a measured or designed meridian,
// interpolated by a natural cubic spline z(rho), which is C2, so normals and their derivatives are
// continuous. Profile parameter s = rho; no shape parameters.

#include "omnisfm/camera/mirror_profile.h"

namespace omnisfm::camera {

class TableProfile final : public MirrorProfile {
 public:
  // rho strictly increasing, at least 4 samples; the valid range must lie inside the table.
  // Throws std::invalid_argument otherwise.
  TableProfile(std::vector<double> rho, std::vector<double> z, double rho_min, double rho_max);

  std::unique_ptr<MirrorProfile> clone() const override;
  MirrorKind kind() const override { return MirrorKind::kTable; }
  int num_shape_params() const override { return 0; }
  std::vector<std::string> shape_param_names() const override { return {}; }
  Eigen::VectorXd shape_params() const override { return {}; }
  bool set_shape_params(const Eigen::VectorXd& params) override { return params.size() == 0; }
  bool set_valid_range(double s_min, double s_max) override;

  void evaluate(double rho, MeridianPoint* point, MeridianShapeJacobian* J_shape) const override;
  double implicit(double rho, double z, double* dG_drho, double* dG_dz) const override;
  double parameter_at(double rho, double z) const override;
  void solve_domain(double* lo, double* hi) const override;

  const std::vector<double>& rho_samples() const { return rho_; }
  const std::vector<double>& z_samples() const { return z_; }

 private:
  // z, dz/drho, d2z/drho2 at rho (cubic inside the table, linear beyond it).
  void spline(double rho, double* z, double* dz, double* d2z) const;
  std::vector<double> rho_, z_, second_;  // second_: spline second derivatives at the samples
};

}  // namespace omnisfm::camera
