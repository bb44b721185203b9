#include "omnisfm/camera/catadioptric_camera.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sin_cos.h"

namespace omnisfm::camera {
namespace {

constexpr int kMaxNewtonIterations = 30;
constexpr int kGuessTableSize = 64;
constexpr int kGuessKeyNodes = 128;
constexpr size_t kGuessRefineStride = 4;
constexpr int kUnprojectMarchSteps = 24;
// Steps below this fraction of the solve domain (and radians in azimuth) mean convergence: far
// below 1e-9 px for any realistic focal length, since Newton converges quadratically.
constexpr double kStepTolerance = 1e-13;
// A reflection must face both the camera and the point by more than this cosine.
constexpr double kMinGrazingCosine = 1e-9;

// The mirror surface and its local frame at (s, phi), in frame M.
struct SurfacePoint {
  MeridianPoint meridian;
  Eigen::Vector3d m, dm_ds, d2m_ds2, e_rho;

  SurfacePoint(const MirrorProfile& mirror, double s, double phi) {
    mirror.evaluate(s, &meridian, nullptr);
    double sn, c;
    sin_cos(phi, &sn, &c);
    e_rho << c, sn, 0;
    m << meridian.rho * c, meridian.rho * sn, meridian.z;
    dm_ds << meridian.drho * c, meridian.drho * sn, meridian.dz;
    d2m_ds2 << meridian.d2rho * c, meridian.d2rho * sn, meridian.d2z;
  }

  // Unit normal on the reflective (camera) side: the meridian tangent turned toward -z, since s
  // grows away from the axis.
  Eigen::Vector3d outward_normal() const {
    return (meridian.dz * e_rho - meridian.drho * Eigen::Vector3d::UnitZ()).normalized();
  }
};

// a + f (b - a), field by field.
template <typename Node>
Node interpolate(const Node& a, const Node& b, double f) {
  const auto mix = [f](double x, double y) { return x + f * (y - x); };
  return {mix(a.key, b.key),
          mix(a.s, b.s),
          mix(a.rho, b.rho),
          mix(a.z, b.z),
          mix(a.ds_cos, b.ds_cos),
          mix(a.ds_cos2, b.ds_cos2),
          mix(a.ds_sin2, b.ds_sin2),
          mix(a.dphi_sin, b.dphi_sin),
          mix(a.dphi_sincos, b.dphi_sincos)};
}

}  // namespace

// The Newton solve's state; at convergence, what the implicit function theorem needs at the
// solution.
struct CatadioptricCamera::NewtonState {
  double s = 0, phi = 0;  // phi relative to the base azimuth
  int iterations = 0;
  MeridianPoint meridian;
  MeridianShapeJacobian J_shape;
  double cos_phi = 1, sin_phi = 0;  // of the absolute azimuth
  double u_local[3] = {0, 0, 0}, v_local[3] = {0, 0, 0};  // unit, in the local frame
  double du = 0, dv = 0;
  double A00 = 0, A01 = 0, A10 = 0, A11 = 0;  // dF/d(s, phi)
};

// What project's Jacobians share at a solved reflection (see project): the local frame S in
// frame C, d pixel / d m_C and d m_local, GK, the reflection equations' derivatives in the
// point (local and frame C), and the unit directions and tangent in the local frame.
struct CatadioptricCamera::ReflectionDerivatives {
  Eigen::Matrix3d S;
  Eigen::Matrix<double, 2, 3> J_pixel_mC, G;
  Eigen::Matrix2d GK;
  Eigen::Matrix<double, 2, 3> dF_dXl, dF_dX_C;
  Eigen::Vector3d u_l, v_l, tangent_l;
};

CatadioptricCamera::CatadioptricCamera(std::unique_ptr<InnerCamera> inner,
                                       std::unique_ptr<MirrorProfile> mirror,
                                       const MirrorPose& mirror_pose, int image_width,
                                       int image_height)
    : inner_(std::move(inner)),
      mirror_(std::move(mirror)),
      pose_(mirror_pose),
      width_(image_width),
      height_(image_height) {
  if (!inner_ || !mirror_) throw std::invalid_argument("catadioptric camera: missing part");
  if (width_ <= 0 || height_ <= 0)
    throw std::invalid_argument("catadioptric camera: image size must be positive");
  if (!pose_.as_vector().allFinite())
    throw std::invalid_argument("catadioptric camera: mirror pose must be finite");
  refresh();
}

CatadioptricCamera CatadioptricCamera::with_wider_patch(double fraction) const {
  CatadioptricCamera wider(*this);
  const double s_min = mirror_->s_min(), s_max = mirror_->s_max();
  const double width = s_max - s_min;
  // Each end on its own, its margin halved until the profile takes it (the equiangular mirror's
  // domain ends near its pole, a table's where its samples do). A refused range changes nothing.
  const auto widest = [fraction](const auto& take) {
    for (double f = fraction; f > fraction / 64; f /= 2)
      if (take(f)) return f;
    return 0.0;
  };
  const double hi = s_max + width * widest([&](double f) {
    return wider.mirror_->set_valid_range(s_min, s_max + f * width);
  });
  widest([&](double f) {
    return wider.mirror_->set_valid_range(std::max(0.0, s_min - f * width), hi);
  });
  wider.refresh();
  return wider;
}

CatadioptricCamera::CatadioptricCamera(const CatadioptricCamera& other)
    : inner_(other.inner_->clone()),
      mirror_(other.mirror_->clone()),
      pose_(other.pose_),
      width_(other.width_),
      height_(other.height_) {
  refresh();
}

CatadioptricCamera& CatadioptricCamera::operator=(const CatadioptricCamera& other) {
  if (this != &other) *this = CatadioptricCamera(other);
  return *this;
}

void CatadioptricCamera::set_mirror_pose(const MirrorPose& pose) {
  pose_ = pose;
  refresh();
}

int CatadioptricCamera::num_params() const {
  return inner_->num_params() + mirror_->num_shape_params() + 5;
}

std::vector<std::string> CatadioptricCamera::param_names() const {
  std::vector<std::string> names = inner_->param_names();
  for (const auto& n : mirror_->shape_param_names()) names.push_back(n);
  for (const char* n : {"mirror_rx", "mirror_ry", "mirror_tx", "mirror_ty", "mirror_tz"})
    names.emplace_back(n);
  return names;
}

Eigen::VectorXd CatadioptricCamera::params() const {
  Eigen::VectorXd v(num_params());
  v << inner_->params(), mirror_->shape_params(), pose_.as_vector();
  return v;
}

bool CatadioptricCamera::set_params(const Eigen::VectorXd& v) {
  if (v.size() != num_params() || !v.allFinite()) return false;
  const int ni = inner_->num_params(), ns = mirror_->num_shape_params();
  const Eigen::VectorXd old_inner = inner_->params();
  if (!inner_->set_params(v.head(ni))) return false;
  if (!mirror_->set_shape_params(v.segment(ni, ns))) {
    inner_->set_params(old_inner);
    return false;
  }
  pose_ = MirrorPose::from_vector(v.tail<5>());
  refresh();
  return true;
}

void CatadioptricCamera::refresh() {
  R_ = pose_.rotation();
  pose_.rotation_derivatives(&dR_drx_, &dR_dry_);
  centre_M_ = -R_.transpose() * pose_.translation();
  toward_camera_M_ = -R_.row(2).transpose();
  const Eigen::Matrix3d* dRs[2] = {&dR_drx_, &dR_dry_};
  for (int j = 0; j < 2; ++j)
    dcamera_M_[j] = -dRs[j]->transpose() *
                    (inner_->is_orthographic() ? Eigen::Vector3d::UnitZ() : pose_.translation());
  mirror_->solve_domain(&domain_lo_, &domain_hi_);

  // Bounding region of the valid patch, for unprojection.
  box_rho_max_ = 0;
  box_z_min_ = INFINITY;
  box_z_max_ = -INFINITY;
  constexpr int kPatchSamples = 64;
  for (int i = 0; i <= kPatchSamples; ++i) {
    const double s = mirror_->s_min() + (mirror_->s_max() - mirror_->s_min()) * i / kPatchSamples;
    MeridianPoint p;
    mirror_->evaluate(s, &p, nullptr);
    box_rho_max_ = std::max(box_rho_max_, p.rho);
    box_z_min_ = std::min(box_z_min_, p.z);
    box_z_max_ = std::max(box_z_max_, p.z);
    if (i == kPatchSamples / 2) patch_z_mid_ = p.z;
  }

  build_guess_table();
}

void CatadioptricCamera::build_guess_table() {
  const bool central = !inner_->is_orthographic();
  guess_.resize(kGuessTableSize);
  std::vector<Eigen::Vector3d> outgoing(kGuessTableSize);
  // The camera's sideways offset: its size, and its azimuth.
  const Eigen::Vector3d& offset = central ? centre_M_ : toward_camera_M_;
  const double offset_size = std::hypot(offset.x(), offset.y());
  guess_offset_inverse_ = offset_size > 0 ? 1 / offset_size : 0.0;
  for (int i = 0; i < kGuessTableSize; ++i) {
    // The aligned, far-point reflection at (s, azimuth 0), where frame M is the local frame.
    const double s = domain_hi_ * (i + 0.5) / kGuessTableSize;
    const SurfacePoint sp(*mirror_, s, 0.0);
    const Eigen::Vector3d n = sp.outward_normal();
    Eigen::Vector3d u(0, 0, -1);
    double du = 0;
    if (central) {
      const Eigen::Vector3d to_camera = Eigen::Vector3d(0, 0, centre_M_.z()) - sp.m;
      du = to_camera.norm();
      u = to_camera / du;
    }
    const Eigen::Vector3d out = 2 * u.dot(n) * n - u;
    // Implicit function theorem there (dF/d(s, phi) is diagonal, w = u + out): d(s, phi)/dc =
    // -A^-1 dF/dc for a sideways move c of the camera's centre, or of its viewing direction.
    const Eigen::Vector3d w = u + out;
    const double u_t = u.dot(sp.dm_ds);
    double A00 = w.dot(sp.d2m_ds2), A11 = -w.x();
    double dF0_dradial = sp.dm_ds.x(), dF1_dtangential = 1;
    if (central) {
      A00 -= (sp.dm_ds.squaredNorm() - u_t * u_t) / du;
      A11 -= sp.meridian.rho / du;
      dF0_dradial = (sp.dm_ds.x() - u_t * u.x()) / du;
      dF1_dtangential /= du;
    }
    // To first order in the offset's size: the sin^2 and sin cos terms are second order.
    guess_[i] = {out.x() / (1 - out.z()),
                 s,
                 sp.meridian.rho,
                 sp.meridian.z,
                 A00 != 0 ? -dF0_dradial / A00 * offset_size : 0.0,
                 0,
                 0,
                 A11 != 0 ? -dF1_dtangential / A11 * offset_size : 0.0,
                 0};
    outgoing[i] = out;
  }

  // Keep the nodes up to where the key stops growing, resampled uniformly in the key so that a
  // look-up is an index; when that leaves out part of the valid patch, search all the nodes for
  // the nearest key instead.
  size_t growing = 1;
  while (growing < guess_.size() && std::isfinite(guess_[growing].key) &&
         guess_[growing].key > guess_[growing - 1].key)
    ++growing;
  guess_monotonic_ = growing >= 2 && guess_[growing - 1].s >= mirror_->s_max();
  if (!guess_monotonic_) return;
  guess_.resize(growing);
  if (offset_size > 0) refine_guess_offsets(outgoing, std::atan2(offset.y(), offset.x()));
  const std::vector<GuessNode> by_s = guess_;
  guess_key_min_ = by_s.front().key;
  const double key_step = (by_s.back().key - guess_key_min_) / (kGuessKeyNodes - 1);
  guess_key_scale_ = 1 / key_step;
  guess_.resize(kGuessKeyNodes);
  size_t j = 0;
  for (int i = 0; i < kGuessKeyNodes; ++i) {
    const double key = guess_key_min_ + key_step * i;
    while (j + 2 < by_s.size() && by_s[j + 1].key <= key) ++j;
    const GuessNode &a = by_s[j], &b = by_s[j + 1];
    guess_[i] = interpolate(a, b, (key - a.key) / (b.key - a.key));
  }
}

void CatadioptricCamera::refine_guess_offsets(const std::vector<Eigen::Vector3d>& outgoing,
                                              double offset_azimuth) {
  // The offset's effect, beyond first order, from exact far-point solutions with the camera's
  // offset at psi = 0, pi/2, pi and pi/4 from the point's azimuth, fitted by
  //   ds = a cos psi + b cos^2 psi + c sin^2 psi,  dphi = d sin psi + e sin psi cos psi.
  // Solved at every kGuessRefineStride-th node; the nodes between get the difference from their
  // own first-order correction interpolated, which varies slowly.
  constexpr double kFarDistance = 1e6;  // metres: parallax far below the solver's tolerance
  constexpr double kPsi[] = {0, M_PI / 2, M_PI, M_PI / 4};
  const auto refined = [&](size_t i, GuessNode* refined_node) {
    GuessNode node = guess_[i];
    double ds[4], dphi[4];
    for (int k = 0; k < 4; ++k) {
      const double psi = kPsi[k], azimuth = offset_azimuth - psi;
      const double c = std::cos(azimuth), sn = std::sin(azimuth);
      const double rho_far = node.rho + kFarDistance * outgoing[i].x();
      const Eigen::Vector3d X_M(rho_far * c, rho_far * sn, node.z + kFarDistance * outgoing[i].z());
      NewtonState state;
      state.s = node.s + node.ds_cos * std::cos(psi);
      state.phi = node.dphi_sin * std::sin(psi);
      if (!solve(X_M, c, sn, false, &state)) return false;
      ds[k] = state.s - node.s;
      dphi[k] = state.phi;
    }
    node.ds_cos = (ds[0] - ds[2]) / 2;
    node.ds_cos2 = (ds[0] + ds[2]) / 2;
    node.ds_sin2 = ds[1];
    node.dphi_sin = dphi[1];
    node.dphi_sincos = 2 * dphi[3] - std::sqrt(2.0) * dphi[1];
    *refined_node = node;
    return true;
  };
  // Differences refined - first order at the solved nodes (zero where a solve failed).
  const size_t n = guess_.size();
  std::vector<size_t> solved_at;
  std::vector<GuessNode> difference;
  for (size_t i = 0; i < n;
       i += std::min<size_t>(kGuessRefineStride, std::max<size_t>(n - 1 - i, 1))) {
    GuessNode node;
    const GuessNode& first = guess_[i];
    GuessNode d{};
    if (refined(i, &node))
      d = {0,
           0,
           0,
           0,
           node.ds_cos - first.ds_cos,
           node.ds_cos2,
           node.ds_sin2,
           node.dphi_sin - first.dphi_sin,
           node.dphi_sincos};
    solved_at.push_back(i);
    difference.push_back(d);
  }
  size_t j = 0;
  for (size_t i = 0; i < n; ++i) {
    while (j + 2 < solved_at.size() && solved_at[j + 1] <= i) ++j;
    const double f =
        solved_at.size() < 2
            ? 0.0
            : std::clamp(static_cast<double>(i - solved_at[j]) / (solved_at[j + 1] - solved_at[j]),
                         0.0, 1.0);
    const GuessNode d =
        solved_at.size() < 2 ? difference[0] : interpolate(difference[j], difference[j + 1], f);
    GuessNode& node = guess_[i];
    node.ds_cos += d.ds_cos;
    node.ds_cos2 += d.ds_cos2;
    node.ds_sin2 += d.ds_sin2;
    node.dphi_sin += d.dphi_sin;
    node.dphi_sincos += d.dphi_sincos;
  }
}

void CatadioptricCamera::initial_guess(const Eigen::Vector3d& X_M, double cos_azimuth,
                                       double sin_azimuth, double* s,
                                       double* azimuth_offset) const {
  const double rho_X = cos_azimuth * X_M.x() + sin_azimuth * X_M.y();
  // The key of the direction to X from (rho, z) in X's meridian plane.
  const auto key_from = [&](double rho, double z) {
    const double a = rho_X - rho, b = X_M.z() - z;
    const double denominator = std::sqrt(a * a + b * b) - b;
    return denominator > 0 ? a / denominator : INFINITY;
  };
  if (!guess_monotonic_) {
    const double key = key_from(0, patch_z_mid_);
    double best_error = INFINITY;
    for (const GuessNode& node : guess_) {
      if (std::abs(node.key - key) < best_error) {
        best_error = std::abs(node.key - key);
        *s = node.s;
      }
    }
    *azimuth_offset = 0;
    return;
  }
  // Linear interpolation between the nodes around key (the end nodes beyond them).
  const auto look_up = [&](double key) {
    const double t =
        std::clamp((key - guess_key_min_) * guess_key_scale_, 0.0, kGuessKeyNodes - 1.0);
    const int i = std::min(static_cast<int>(t), kGuessKeyNodes - 2);
    return interpolate(guess_[i], guess_[i + 1], t - i);
  };
  // The direction of the camera's sideways offset from X's azimuth: cos psi, sin psi.
  const Eigen::Vector3d& offset = inner_->is_orthographic() ? toward_camera_M_ : centre_M_;
  const double cos_psi =
      (cos_azimuth * offset.x() + sin_azimuth * offset.y()) * guess_offset_inverse_;
  const double sin_psi =
      (cos_azimuth * offset.y() - sin_azimuth * offset.x()) * guess_offset_inverse_;
  // From the middle of the patch, then again from the mirror point found.
  GuessNode node = look_up(key_from(0, patch_z_mid_));
  node = look_up(key_from(node.rho, node.z));
  *s = node.s + cos_psi * (node.ds_cos + cos_psi * node.ds_cos2) + sin_psi * sin_psi * node.ds_sin2;
  *azimuth_offset = sin_psi * (node.dphi_sin + cos_psi * node.dphi_sincos);
}

bool CatadioptricCamera::solve(const Eigen::Vector3d& X_M, double cos_base, double sin_base,
                               bool want_shape, NewtonState* state) const {
  // Newton's method on F(s, phi) = (w . dm/ds, w . e_phi), w = unit(camera - m) + unit(X - m),
  // worked in the frame (e_rho, e_phi, z) of the current azimuth: there m = (rho, 0, z), dm/ds =
  // (drho, 0, dz) and d2m/ds2 = (d2rho, 0, d2z), so F and its Jacobian A reduce to a few products.
  // dw/dm (W = -(I - v v^T)/dv - (I - u u^T)/du) enters only through such products.
  const bool central = !inner_->is_orthographic();
  const double s_scale = domain_hi_;
  NewtonState& n = *state;
  MeridianPoint& mp = n.meridian;
  double &cos_phi = n.cos_phi, &sin_phi = n.sin_phi, &s = n.s, &phi = n.phi;
  double *u_local = n.u_local, *v_local = n.v_local;
  int& iteration = n.iterations;
  bool converged = false;
  int boundary_hits = 0;
  for (iteration = 0; iteration < kMaxNewtonIterations; ++iteration) {
    // With parameter Jacobians wanted, the shape derivatives come with every evaluation: the last
    // one is at the solution, which saves evaluating the surface again.
    mirror_->evaluate(s, &mp, want_shape ? &n.J_shape : nullptr);
    double sin_offset, cos_offset;
    sin_cos(phi, &sin_offset, &cos_offset);
    cos_phi = cos_base * cos_offset - sin_base * sin_offset;
    sin_phi = sin_base * cos_offset + cos_base * sin_offset;
    const auto to_local = [&](const Eigen::Vector3d& x, double* out) {
      out[0] = cos_phi * x.x() + sin_phi * x.y();
      out[1] = cos_phi * x.y() - sin_phi * x.x();
      out[2] = x.z();
    };
    to_local(X_M, v_local);
    v_local[0] -= mp.rho;
    v_local[2] -= mp.z;
    const double dv = n.dv =
        std::sqrt(v_local[0] * v_local[0] + v_local[1] * v_local[1] + v_local[2] * v_local[2]);
    if (!(dv > 1e-12)) return false;
    const double inv_dv = 1 / dv;
    double inv_du = 0;  // no dw/dm term from a fixed viewing direction
    if (central) {
      to_local(centre_M_, u_local);
      u_local[0] -= mp.rho;
      u_local[2] -= mp.z;
      const double du = n.du =
          std::sqrt(u_local[0] * u_local[0] + u_local[1] * u_local[1] + u_local[2] * u_local[2]);
      if (!(du > 1e-12)) return false;
      inv_du = 1 / du;
      for (int k = 0; k < 3; ++k) u_local[k] *= inv_du;
    } else {
      to_local(toward_camera_M_, u_local);
    }
    for (int k = 0; k < 3; ++k) v_local[k] *= inv_dv;
    const double w0 = u_local[0] + v_local[0], w1 = u_local[1] + v_local[1],
                 w2 = u_local[2] + v_local[2];
    const double F0 = w0 * mp.drho + w2 * mp.dz, F1 = w1;
    const double v_t = v_local[0] * mp.drho + v_local[2] * mp.dz;
    const double u_t = u_local[0] * mp.drho + u_local[2] * mp.dz;
    const double t_t = mp.drho * mp.drho + mp.dz * mp.dz;
    const double A00 = n.A00 =
        -(t_t - v_t * v_t) * inv_dv - (t_t - u_t * u_t) * inv_du + w0 * mp.d2rho + w2 * mp.d2z;
    const double A10 = n.A10 = v_t * v_local[1] * inv_dv + u_t * u_local[1] * inv_du;
    const double A01 = n.A01 = mp.rho * A10 + mp.drho * F1;
    const double A11 = n.A11 = -mp.rho * ((1 - v_local[1] * v_local[1]) * inv_dv +
                                          (1 - u_local[1] * u_local[1]) * inv_du) -
                               w0;
    const double det = A00 * A11 - A01 * A10;
    if (!(std::abs(det) > 0) || !std::isfinite(det)) return false;
    double step_s = -(A11 * F0 - A01 * F1) / det;
    double step_phi = -(A00 * F1 - A10 * F0) / det;
    if (std::abs(step_s) < kStepTolerance * s_scale && std::abs(step_phi) < kStepTolerance) {
      converged = true;
      break;
    }
    // Damp wild first steps; the solution is near the aligned guess.
    s += std::clamp(step_s, -0.25 * s_scale, 0.25 * s_scale);
    phi += std::clamp(step_phi, -0.5, 0.5);
    if (s < domain_lo_ || s > domain_hi_) {
      s = std::clamp(s, domain_lo_, domain_hi_);
      if (++boundary_hits > 2) return false;
    }
  }
  return converged;
}

bool CatadioptricCamera::project(const Eigen::Vector3d& X, Eigen::Vector2d* pixel,
                                 Eigen::Matrix<double, 2, 3>* J_X, ParamsJacobian* J_params,
                                 Reflection* reflection) const {
  // The camera's own centre sees only itself.
  if (!X.allFinite() || (!inner_->is_orthographic() && X.norm() < 1e-12)) return false;
  const Eigen::Vector3d& t = pose_.translation();
  const Eigen::Vector3d X_M = R_.transpose() * (X - t);
  const bool want_jacobians = J_X || J_params;

  // The azimuth is carried as an offset phi from X's own, whose cosine and sine need no
  // trigonometry (on the axis any azimuth will do).
  const double rho_X = std::sqrt(X_M.x() * X_M.x() + X_M.y() * X_M.y());
  const double cos_base = rho_X > 0 ? X_M.x() / rho_X : 1.0;
  const double sin_base = rho_X > 0 ? X_M.y() / rho_X : 0.0;
  NewtonState state;
  initial_guess(X_M, cos_base, sin_base, &state.s, &state.phi);
  if (!solve(X_M, cos_base, sin_base, J_params && mirror_->num_shape_params() > 0, &state))
    return false;
  const double s = state.s;
  const MeridianPoint& mp = state.meridian;
  const double cos_phi = state.cos_phi, sin_phi = state.sin_phi, dv = state.dv;
  const double *u_local = state.u_local, *v_local = state.v_local;
  const double A00 = state.A00, A01 = state.A01, A10 = state.A10, A11 = state.A11;
  const int iteration = state.iterations;
  // The same point named with a positive profile parameter; the derivatives below keep the
  // solver's (s, phi), which sp describes.
  const double s_positive = std::abs(s);
  if (!mirror_->is_valid_parameter(s_positive)) return false;

  // The reflection must happen on the mirror's front face, seen by both camera and point: the
  // outward normal is (dz, 0, -drho) in the local frame.
  const Eigen::Vector3d u_l(u_local[0], u_local[1], u_local[2]);
  const Eigen::Vector3d v_l(v_local[0], v_local[1], v_local[2]);
  const Eigen::Vector3d normal_l = Eigen::Vector3d(mp.dz, 0, -mp.drho).normalized();
  if (!(u_l.dot(normal_l) > kMinGrazingCosine) || !(v_l.dot(normal_l) > kMinGrazingCosine))
    return false;

  // The local frame in frame C: S = R [e_rho e_phi z].
  Eigen::Matrix3d S;
  S << cos_phi * R_.col(0) + sin_phi * R_.col(1), cos_phi * R_.col(1) - sin_phi * R_.col(0),
      R_.col(2);
  const Eigen::Vector3d m_C = S * Eigen::Vector3d(mp.rho, 0, mp.z) + t;
  Eigen::Matrix<double, 2, 3> J_pixel_mC;
  // The inner camera's columns come first.
  thread_local ParamsJacobian J_inner;
  if (!inner_->project(m_C, pixel, want_jacobians ? &J_pixel_mC : nullptr,
                       J_params ? &J_inner : nullptr))
    return false;
  if (reflection)
    *reflection = {s_positive, std::atan2(s < 0 ? -sin_phi : sin_phi, s < 0 ? -cos_phi : cos_phi),
                   m_C, iteration};
  if (!want_jacobians) return true;

  // Implicit function theorem, in the local frame: d(s, phi)/dy = -A^-1 dF/dy moves m by
  // dm/d(s, phi) = [t, rho e_phi], t = (drho, 0, dz); so d pixel / dy = GK dF/dy (+ direct terms)
  // with G = d pixel / d m_local and GK = -G [t, rho e_phi] A^-1.
  const Eigen::Matrix<double, 2, 3> G = J_pixel_mC * S;
  Eigen::Matrix2d G_dm_dsphi;
  G_dm_dsphi << G.col(0) * mp.drho + G.col(2) * mp.dz, G.col(1) * mp.rho;
  Eigen::Matrix2d A;
  A << A00, A01, A10, A11;
  const Eigen::Matrix2d GK = -G_dm_dsphi * A.inverse();
  // dF/dX_local = P (I - v v^T) / dv, P = [t, e_phi]^T; the same with u for the camera's centre.
  const Eigen::Vector3d tangent_l(mp.drho, 0, mp.dz);
  const auto dF_dtarget = [&](const Eigen::Vector3d& unit, double inverse_distance) {
    Eigen::Matrix<double, 2, 3> d;
    d.row(0) = (tangent_l - unit * unit.dot(tangent_l)).transpose() * inverse_distance;
    d.row(1) = (Eigen::Vector3d::UnitY() - unit * unit.y()).transpose() * inverse_distance;
    return d;
  };
  const Eigen::Matrix<double, 2, 3> dF_dXl = dF_dtarget(v_l, 1 / dv);
  const Eigen::Matrix<double, 2, 3> dF_dX_C = dF_dXl * S.transpose();
  if (J_X) *J_X = GK * dF_dX_C;
  if (!J_params) return true;
  params_jacobian(X, state, {S, J_pixel_mC, G, GK, dF_dXl, dF_dX_C, u_l, v_l, tangent_l}, J_inner,
                  J_params);
  return true;
}

void CatadioptricCamera::params_jacobian(const Eigen::Vector3d& X, const NewtonState& state,
                                         const ReflectionDerivatives& d,
                                         const ParamsJacobian& J_inner,
                                         ParamsJacobian* J_params) const {
  const bool central = !inner_->is_orthographic();
  const Eigen::Vector3d& t = pose_.translation();
  const MeridianPoint& mp = state.meridian;
  const MeridianShapeJacobian& J_shape = state.J_shape;
  const double cos_phi = state.cos_phi, sin_phi = state.sin_phi, du = state.du, dv = state.dv;
  const Eigen::Matrix3d& S = d.S;
  const Eigen::Matrix<double, 2, 3>&J_pixel_mC = d.J_pixel_mC, &G = d.G, &dF_dXl = d.dF_dXl,
                              &dF_dX_C = d.dF_dX_C;
  const Eigen::Matrix2d& GK = d.GK;
  const Eigen::Vector3d &u_l = d.u_l, &v_l = d.v_l, &tangent_l = d.tangent_l;
  const auto dF_dtarget = [&](const Eigen::Vector3d& unit, double inverse_distance) {
    Eigen::Matrix<double, 2, 3> dF;
    dF.row(0) = (tangent_l - unit * unit.dot(tangent_l)).transpose() * inverse_distance;
    dF.row(1) = (Eigen::Vector3d::UnitY() - unit * unit.y()).transpose() * inverse_distance;
    return dF;
  };

  J_params->resize(2, num_params());
  J_params->leftCols(J_inner.cols()) = J_inner;
  const int ns = mirror_->num_shape_params();
  const double inv_dv = 1 / dv, inv_du = central ? 1 / du : 0.0;
  const Eigen::Vector3d w_l = u_l + v_l;
  for (int j = 0; j < ns; ++j) {
    // The surface point and its tangent move in the meridian plane; dw/dm = W applied to that.
    const Eigen::Vector3d dm(J_shape(0, j), 0, J_shape(1, j));
    const Eigen::Vector3d W_dm =
        -(dm - v_l * v_l.dot(dm)) * inv_dv - (dm - u_l * u_l.dot(dm)) * inv_du;
    const double w_dtangent = w_l.x() * J_shape(2, j) + w_l.z() * J_shape(3, j);
    const Eigen::Vector2d dF(tangent_l.dot(W_dm) + w_dtangent, W_dm.y());
    J_params->col(shape_param_offset() + j) = GK * dF + G * dm;
  }

  // Mirror pose: X_M = R^T (X - t); the camera's centre -R^T t, or its direction -R^T z.
  const Eigen::Matrix<double, 2, 3> dF_dcamera_l =
      central ? dF_dtarget(u_l, inv_du)
              : (Eigen::Matrix<double, 2, 3>() << tangent_l.transpose(), 0, 1, 0).finished();
  const auto to_local = [&](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(cos_phi * x.x() + sin_phi * x.y(), cos_phi * x.y() - sin_phi * x.x(),
                           x.z());
  };
  const Eigen::Vector3d m_M(cos_phi * mp.rho, sin_phi * mp.rho, mp.z);
  const int po = pose_param_offset();
  const Eigen::Matrix3d* dRs[2] = {&dR_drx_, &dR_dry_};
  for (int j = 0; j < 2; ++j) {
    const Eigen::Vector2d dF =
        dF_dXl * to_local(dRs[j]->transpose() * (X - t)) + dF_dcamera_l * to_local(dcamera_M_[j]);
    J_params->col(po + j) = J_pixel_mC * (*dRs[j] * m_M) + GK * dF;
  }
  auto J_t = J_params->middleCols<3>(po + 2);
  if (central)
    J_t = J_pixel_mC - GK * ((dF_dXl + dF_dcamera_l) * S.transpose());
  else
    J_t = J_pixel_mC - GK * dF_dX_C;
}

bool CatadioptricCamera::unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                                   Eigen::Vector3d* direction, RayJacobian* J,
                                   bool with_params) const {
  Eigen::Vector3d o_C, d_C;
  if (!pixel.allFinite() || !inner_->unproject(pixel, &o_C, &d_C)) return false;
  const Eigen::Vector3d& t = pose_.translation();
  const Eigen::Vector3d o = R_.transpose() * (o_C - t);
  const Eigen::Vector3d d = R_.transpose() * d_C;

  // The stretch of the ray inside the bounding cylinder and slab of the valid patch.
  const double margin = 0.05 * (box_z_max_ - box_z_min_ + box_rho_max_);
  double lo = 0, hi = INFINITY;
  const double z_lo = box_z_min_ - margin, z_hi = box_z_max_ + margin;
  if (std::abs(d.z()) > 1e-15) {
    double a = (z_lo - o.z()) / d.z(), b = (z_hi - o.z()) / d.z();
    if (a > b) std::swap(a, b);
    lo = std::max(lo, a);
    hi = std::min(hi, b);
  } else if (o.z() < z_lo || o.z() > z_hi) {
    return false;
  }
  const double radius = box_rho_max_ + margin;
  const double qa = d.x() * d.x() + d.y() * d.y();
  const double qb = 2 * (o.x() * d.x() + o.y() * d.y());
  const double qc = o.x() * o.x() + o.y() * o.y() - radius * radius;
  if (qa > 1e-30) {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) return false;
    const double root = std::sqrt(disc);
    lo = std::max(lo, (-qb - root) / (2 * qa));
    hi = std::min(hi, (-qb + root) / (2 * qa));
  } else if (qc > 0) {
    return false;
  }
  if (!(hi > lo)) return false;

  auto implicit_along = [&](double lambda, double* derivative) {
    const Eigen::Vector3d p = o + lambda * d;
    const double rho = std::hypot(p.x(), p.y());
    double dG_drho, dG_dz;
    const double G = mirror_->implicit(rho, p.z(), &dG_drho, &dG_dz);
    const double drho = rho > 0 ? (p.x() * d.x() + p.y() * d.y()) / rho : std::hypot(d.x(), d.y());
    *derivative = dG_drho * drho + dG_dz * d.z();
    return G;
  };

  // March to the first crossing from the camera's side (G < 0) to behind the mirror.
  double a = lo, dG;
  double Ga = implicit_along(a, &dG);
  double b = a, Gb = Ga;
  bool bracketed = false;
  for (int i = 1; i <= kUnprojectMarchSteps; ++i) {
    b = lo + (hi - lo) * i / kUnprojectMarchSteps;
    Gb = implicit_along(b, &dG);
    if (Ga < 0 && Gb >= 0) {
      bracketed = true;
      break;
    }
    a = b;
    Ga = Gb;
  }
  if (!bracketed) return false;

  // Newton's method kept inside the bracket, bisecting when a step would leave it.
  double lambda = b - Gb * (b - a) / (Gb - Ga);
  for (int it = 0; it < 100; ++it) {
    const double G = implicit_along(lambda, &dG);
    if (G < 0)
      a = lambda;
    else
      b = lambda;
    double next = lambda - G / dG;
    if (!(next > a && next < b)) next = 0.5 * (a + b);
    const double change = std::abs(next - lambda);
    lambda = next;
    if (change <= 1e-15 * std::max(1.0, std::abs(lambda)) || b - a <= 1e-16 * std::abs(lambda))
      break;
  }

  const Eigen::Vector3d p = o + lambda * d;
  const double s = mirror_->parameter_at(std::hypot(p.x(), p.y()), p.z());
  if (!mirror_->is_valid_parameter(s)) return false;
  const SurfacePoint sp(*mirror_, s, std::atan2(p.y(), p.x()));
  const Eigen::Vector3d normal = sp.outward_normal();
  const double incidence = d.dot(normal);
  if (!(incidence < -kMinGrazingCosine)) return false;
  const Eigen::Vector3d reflected = d - 2 * incidence * normal;
  *origin = R_ * p + t;
  *direction = (R_ * reflected).normalized();
  if (!origin->allFinite() || !direction->allFinite()) return false;
  return !J || ray_jacobian(*origin, *direction, J, with_params);
}

bool CatadioptricCamera::ray_jacobian(const Eigen::Vector3d& origin,
                                      const Eigen::Vector3d& direction, RayJacobian* J,
                                      bool with_params) const {
  // Two points of the ray at scene distances, scaled by the mirror's size: far enough from it to
  // project well, far enough apart to turn the ray accurately.
  const double near = 20 * box_rho_max_, far = 200 * box_rho_max_;
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - direction * direction.transpose();
  Eigen::Matrix<double, 3, 2> move_pixel[2];
  Eigen::Matrix<double, 3, Eigen::Dynamic> move_params[2];
  thread_local ParamsJacobian J_params;
  for (int k = 0; k < 2; ++k) {
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 3> J_X;
    if (!project(origin + (k == 0 ? near : far) * direction, &pixel, &J_X,
                 with_params ? &J_params : nullptr))
      return false;
    // J_X's pseudo-inverse, J_X^T (J_X J_X^T)^-1: the least-norm dX per pixel.
    const Eigen::Matrix<double, 3, 2> least_norm =
        across * J_X.transpose() * (J_X * J_X.transpose()).inverse();
    move_pixel[k] = least_norm;
    if (with_params) move_params[k] = -least_norm * J_params;
  }
  J->direction_pixel = (move_pixel[1] - move_pixel[0]) / (far - near);
  J->origin_pixel = move_pixel[0] - near * J->direction_pixel;
  if (with_params) {
    J->direction_params = (move_params[1] - move_params[0]) / (far - near);
    J->origin_params = move_params[0] - near * J->direction_params;
  }
  return J->direction_pixel.allFinite() && J->origin_pixel.allFinite();
}

}  // namespace omnisfm::camera
