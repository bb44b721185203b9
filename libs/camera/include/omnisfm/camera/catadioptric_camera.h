#pragma once
// The exact, generally noncentral, catadioptric camera: an inner camera looking at a mirror of
// revolution placed by a 5-DOF mirror-to-camera transform.
//
// Projection of X (frame C): the mirror point m(s, phi) where the angle of incidence equals the
// angle of reflection between the directions to X and to the inner camera (the camera's centre, or
// -z for an orthographic camera). With w = unit(camera - m) + unit(X - m), the two equations
//   F(s, phi) = ( w . dm/ds ,  w . e_phi ) = 0
// (w along the normal) are solved by Newton's method from the aligned solution, then m is
// projected by the inner camera. Derivatives come from the implicit function theorem:
//   d(s, phi)/dy = -(dF/d(s, phi))^-1 dF/dy   for y = X, shape, the mirror pose.
//
// Unprojection: inner camera ray -> first intersection with the mirror -> reflected ray, returned
// as an origin on the mirror and a unit direction, in frame C.
//
// A point or pixel with no valid reflection (behind the mirror, beyond the rim, in the camera's own
// reflection, on the axis, at the camera) is reported invalid; outputs are then left unspecified.
//
// Parameters, wherever they appear as one vector: the inner camera's, then the mirror shape's,
// then the mirror pose (rx ry tx ty tz).

#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "omnisfm/camera/inner_camera.h"
#include "omnisfm/camera/mirror_pose.h"
#include "omnisfm/camera/mirror_profile.h"

namespace omnisfm::camera {

// Where a projected point reflects, in the mirror frame.
struct Reflection {
  double s = 0, phi = 0;      // profile parameter and azimuth
  Eigen::Vector3d point_C;    // the mirror point in frame C
  int iterations = 0;         // Newton iterations used
};

// How a pixel's reflected ray moves, to first order, with the pixel and with params(): the
// direction's change, and the origin's move across the ray (perpendicular to it: a move along the
// ray changes the ray nothing, only where it is said to start).
struct RayJacobian {
  Eigen::Matrix<double, 3, 2> direction_pixel, origin_pixel;
  // 3 x num_params(); filled only when asked for (unproject's with_params).
  Eigen::Matrix<double, 3, Eigen::Dynamic> direction_params, origin_params;
};

class CatadioptricCamera {
 public:
  CatadioptricCamera(std::unique_ptr<InnerCamera> inner, std::unique_ptr<MirrorProfile> mirror,
                     const MirrorPose& mirror_pose, int image_width, int image_height);
  CatadioptricCamera(const CatadioptricCamera& other);
  CatadioptricCamera& operator=(const CatadioptricCamera& other);
  CatadioptricCamera(CatadioptricCamera&&) noexcept = default;
  CatadioptricCamera& operator=(CatadioptricCamera&&) noexcept = default;

  // Pixel of a point X in frame C. J_X: d pixel / d X. J_params: d pixel / d params() (resized
  // to 2 x num_params()). Returns false where X has no valid reflection.
  bool project(const Eigen::Vector3d& X, Eigen::Vector2d* pixel,
               Eigen::Matrix<double, 2, 3>* J_X = nullptr, ParamsJacobian* J_params = nullptr,
               Reflection* reflection = nullptr) const;

  // The reflected ray of a pixel, in frame C: origin on the mirror, unit direction. With J, its
  // derivatives (with_params: in params() too), from the implicit function theorem on projection:
  // the points of the ray stay at the pixel, and J_X's null space is the ray itself, so the
  // least-norm solution of J_X dX = dpixel - J_params dparams is the ray's move across itself at
  // X; two points of the ray give its turn and its shift. False also where those points do not
  // project (the ray leaving through the camera's own reflection).
  bool unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin, Eigen::Vector3d* direction,
                 RayJacobian* J = nullptr, bool with_params = false) const;

  int num_params() const;
  std::vector<std::string> param_names() const;
  Eigen::VectorXd params() const;
  // Returns false, changing nothing, when any part is out of its domain.
  bool set_params(const Eigen::VectorXd& params);
  int shape_param_offset() const { return inner_->num_params(); }
  int pose_param_offset() const { return inner_->num_params() + mirror_->num_shape_params(); }

  // A copy whose valid patch reaches `fraction` of its width further at both ends (the rim and
  // the camera's own reflection), or less, or not at all, where the profile's domain ends first
  // (a table's where its samples do). For estimators: a point seen just inside the rim is as
  // often predicted just outside it, and a solver stalls against a wall of invalid projections.
  CatadioptricCamera with_wider_patch(double fraction) const;

  const InnerCamera& inner() const { return *inner_; }
  const MirrorProfile& mirror() const { return *mirror_; }
  const MirrorPose& mirror_pose() const { return pose_; }
  void set_mirror_pose(const MirrorPose& pose);
  int image_width() const { return width_; }
  int image_height() const { return height_; }
  bool in_image(const Eigen::Vector2d& pixel) const {
    return pixel.x() >= -0.5 && pixel.y() >= -0.5 && pixel.x() <= width_ - 0.5 &&
           pixel.y() <= height_ - 0.5;
  }

 private:
  // Rebuilds what is derived from the parameters: rotation, the starting-guess table.
  void refresh();
  // unproject's Jacobian of the ray (origin, direction).
  bool ray_jacobian(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                    RayJacobian* J, bool with_params) const;
  // The starting point of the Newton solve for X_M: profile parameter, and azimuth relative to
  // X_M's own, whose cosine and sine are given.
  void initial_guess(const Eigen::Vector3d& X_M, double cos_azimuth, double sin_azimuth,
                     double* s, double* azimuth_offset) const;
  void build_guess_table();
  void refine_guess_offsets(const std::vector<Eigen::Vector3d>& outgoing, double offset_azimuth);
  // Newton's method on the incidence = reflection equations for X_M, from state's (s, phi), phi
  // relative to the azimuth whose cosine and sine are given. Returns false without convergence.
  struct NewtonState;
  bool solve(const Eigen::Vector3d& X_M, double cos_base, double sin_base, bool want_shape,
             NewtonState* state) const;
  // project's J_params at the reflection `state` solved for X (frame C), the inner camera's
  // columns J_inner first.
  struct ReflectionDerivatives;
  void params_jacobian(const Eigen::Vector3d& X, const NewtonState& state,
                       const ReflectionDerivatives& d, const ParamsJacobian& J_inner,
                       ParamsJacobian* J_params) const;

  std::unique_ptr<InnerCamera> inner_;
  std::unique_ptr<MirrorProfile> mirror_;
  MirrorPose pose_;
  int width_ = 0, height_ = 0;

  // Derived from the parameters by refresh().
  Eigen::Matrix3d R_;                   // camera_from_mirror
  Eigen::Matrix3d dR_drx_, dR_dry_;
  Eigen::Vector3d centre_M_;            // inner camera centre in frame M (central cameras)
  Eigen::Vector3d toward_camera_M_;     // -z of C in frame M (orthographic cameras)
  Eigen::Vector3d dcamera_M_[2];        // d centre_M_ (or toward_camera_M_) / d rx, ry
  double domain_lo_ = 0, domain_hi_ = 0;
  double patch_z_mid_ = 0;              // a representative height of the valid patch
  double box_rho_max_ = 0, box_z_min_ = 0, box_z_max_ = 0;  // bounding region of the patch
  // The starting guess: the far-point solution of the mirror aligned with a camera on its axis at
  // the actual height, tabulated with key = tan(b / 2), b the outgoing ray's angle from -z
  // (no flat spot at b = 0, unlike cos b). Each node also holds the mirror point, for a second
  // look-up from it (parallax of near points), and the change of the solution with the camera's
  // sideways offset from the axis (its centre, or for an orthographic camera its viewing
  // direction): to first order by the implicit function theorem, refined by exact far-point
  // solutions where the camera is misaligned.
  struct GuessNode {
    double key, s, rho, z;
    // Change of the solution with the offset at angle psi from the point's azimuth (see
    // refine_guess_offsets): ds = ds_cos cos psi + ds_cos2 cos^2 psi + ds_sin2 sin^2 psi,
    // dphi = dphi_sin sin psi + dphi_sincos sin psi cos psi.
    double ds_cos, ds_cos2, ds_sin2, dphi_sin, dphi_sincos;
  };
  // Uniform in the key from guess_key_min_, guess_key_scale_ nodes per unit, while the key grows
  // with s; otherwise (guess_monotonic_ false) uniform in s.
  std::vector<GuessNode> guess_;
  bool guess_monotonic_ = false;
  double guess_key_min_ = 0, guess_key_scale_ = 0;
  double guess_offset_inverse_ = 0;  // 1 / size of the camera's sideways offset (0 if none)
};

}  // namespace omnisfm::camera
