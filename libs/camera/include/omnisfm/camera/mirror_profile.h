#pragma once
// A mirror profile: a surface of revolution about the mirror frame's z axis, given by its meridian
// curve (rho(s), z(s)) in a profile parameter s that grows away from the axis:
//   m(s, phi) = (rho(s) cos phi, rho(s) sin phi, z(s)).
// The valid patch is s in [s_min, s_max]: below s_min the camera sees itself, above s_max is the rim.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace omnisfm::camera {

// A point of the meridian curve and its derivatives with respect to the profile parameter s.
struct MeridianPoint {
  double rho = 0, z = 0;      // distance from the axis, height along the axis
  double drho = 0, dz = 0;    // d/ds
  double d2rho = 0, d2z = 0;  // d2/ds2
};

// Named, and made from numbers, in camera_kinds.h.
enum class MirrorKind { kEquiangular, kConic, kTable };

// Most shape parameters any profile has.
constexpr int kMaxShapeParams = 3;

// Derivatives of (rho, z, drho, dz) with respect to the shape parameters; only the first
// num_shape_params() columns are meaningful.
using MeridianShapeJacobian = Eigen::Matrix<double, 4, kMaxShapeParams>;

class MirrorProfile {
 public:
  virtual ~MirrorProfile() = default;
  virtual std::unique_ptr<MirrorProfile> clone() const = 0;

  virtual MirrorKind kind() const = 0;

  virtual int num_shape_params() const = 0;
  virtual std::vector<std::string> shape_param_names() const = 0;
  virtual Eigen::VectorXd shape_params() const = 0;
  // Returns false, changing nothing, when the values are outside the profile's domain.
  virtual bool set_shape_params(const Eigen::VectorXd& params) = 0;

  double s_min() const { return s_min_; }
  double s_max() const { return s_max_; }
  // Returns false, changing nothing, when the range is empty or outside the profile's domain.
  virtual bool set_valid_range(double s_min, double s_max) = 0;
  bool is_valid_parameter(double s) const { return s >= s_min_ && s <= s_max_; }

  // The meridian point at s, and optionally its shape derivatives. s must lie inside the
  // profile's domain (see solve_domain()); the valid patch is a sub-range of it. rho is odd and
  // z even in s.
  virtual void evaluate(double s, MeridianPoint* point, MeridianShapeJacobian* J_shape) const = 0;

  // An implicit form G(rho, z) of the surface, negative on the camera's side (in front of the
  // reflective face), with its gradient. Defined over the whole bounding region of the patch.
  virtual double implicit(double rho, double z, double* dG_drho, double* dG_dz) const = 0;

  // The profile parameter of the surface point nearest (rho, z); exact for points on the surface.
  virtual double parameter_at(double rho, double z) const = 0;

  // A range of s, wider than the valid patch, over which evaluate() is well defined and a
  // solver may move freely before validity is checked. It is symmetric, [-hi, hi]: evaluate()
  // continues the meridian through the axis, m(-s, phi) = m(s, phi + pi), so that a solver can
  // cross the axis.
  virtual void solve_domain(double* lo, double* hi) const = 0;

 protected:
  double s_min_ = 0, s_max_ = 0;
};

}  // namespace omnisfm::camera
