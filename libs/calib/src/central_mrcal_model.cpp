#include "omnisfm/calib/central_mrcal_model.h"

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "omnisfm/camera/mrcal_lensmodel.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::calib {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kCoreSize = 4;  // fx fy cx cy
// Widening of the spline's domain beyond the widest sampled ray, degrees of fov_x_deg.
constexpr int kFovMarginDeg = 2;
// The widest ray a stereographic model can take with a usable spline domain.
constexpr double kWidestAngleDeg = 170;
// A prior pulling each control point's correction du toward zero: its residual is this times the
// pixels the correction moves (about f du). Weak enough to leave the fit unchanged where samples
// pin the spline down, strong enough to keep control points that few samples reach in place.
constexpr double kRegularization = 1e-4;

bool project_in_model_frame(const mrcal_lensmodel_t& lensmodel, const Eigen::VectorXd& intrinsics,
                            const Eigen::Vector3d& p, Eigen::Vector2d* pixel) {
  const mrcal_point3_t point = {{p.x(), p.y(), p.z()}};
  mrcal_point2_t q;
  if (!mrcal_project(&q, nullptr, nullptr, &point, 1, &lensmodel, intrinsics.data())) return false;
  *pixel << q.x, q.y;
  return pixel->allFinite();
}

// The point with the least sum of squared distances to the rays.
Eigen::Vector3d point_nearest_to(const std::vector<PixelRay>& rays) {
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const PixelRay& ray : rays) {
    const Eigen::Matrix3d across =
        Eigen::Matrix3d::Identity() - ray.direction * ray.direction.transpose();
    normal += across;
    rhs += across * ray.origin;
  }
  return normal.ldlt().solve(rhs);
}

// mrcal's normalised stereographic coordinates of p: 2 tan(angle from z / 2) toward p.
Eigen::Vector2d stereographic(const Eigen::Vector3d& p) {
  return 2 * p.head<2>() / (p.norm() + p.z());
}

// fx, cx (or fy, cy) of q = f u + c, the plain stereographic fit the spline starts from.
Eigen::Vector2d fit_line(const std::vector<double>& u, const std::vector<double>& q) {
  Eigen::MatrixXd A(u.size(), 2);
  Eigen::VectorXd b(u.size());
  for (std::size_t i = 0; i < u.size(); ++i) {
    A(i, 0) = u[i];
    A(i, 1) = 1;
    b[i] = q[i];
  }
  return A.colPivHouseholderQr().solve(b);
}

// One sample's pixel residual. Its parameter blocks are the core and the control points the
// point's spline patch weighs (each an (x, y) pair, interleaved in mrcal's intrinsics); the
// patch depends on the point only, which stays fixed, so it is found once.
class SplinedProjectionResidual : public ceres::CostFunction {
 public:
  SplinedProjectionResidual(const mrcal_lensmodel_t* lensmodel, int num_intrinsics,
                            const Eigen::Vector3d& point, const Eigen::Vector2d& pixel,
                            std::vector<int> control_point_offsets)
      : lensmodel_(lensmodel),
        num_intrinsics_(num_intrinsics),
        point_(point),
        pixel_(pixel),
        offsets_(std::move(control_point_offsets)) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(kCoreSize);
    for (std::size_t i = 0; i < offsets_.size(); ++i) mutable_parameter_block_sizes()->push_back(2);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    // Control points outside the patch do not move this pixel; zero stands in for them.
    thread_local std::vector<double> intrinsics, gradient;
    intrinsics.assign(num_intrinsics_, 0.0);
    std::copy(parameters[0], parameters[0] + kCoreSize, intrinsics.begin());
    for (std::size_t i = 0; i < offsets_.size(); ++i) {
      intrinsics[offsets_[i]] = parameters[1 + i][0];
      intrinsics[offsets_[i] + 1] = parameters[1 + i][1];
    }
    if (jacobians) gradient.resize(2 * num_intrinsics_);
    const mrcal_point3_t p = {{point_.x(), point_.y(), point_.z()}};
    mrcal_point2_t q;
    if (!mrcal_project(&q, nullptr, jacobians ? gradient.data() : nullptr, &p, 1, lensmodel_,
                       intrinsics.data()))
      return false;
    residuals[0] = q.x - pixel_.x();
    residuals[1] = q.y - pixel_.y();
    if (!std::isfinite(residuals[0]) || !std::isfinite(residuals[1])) return false;
    if (!jacobians) return true;
    // mrcal's gradient is row-major 2 x num_intrinsics, as are Ceres' blocks.
    const double* row_x = gradient.data();
    const double* row_y = gradient.data() + num_intrinsics_;
    if (jacobians[0]) {
      for (int j = 0; j < kCoreSize; ++j) {
        jacobians[0][j] = row_x[j];
        jacobians[0][kCoreSize + j] = row_y[j];
      }
    }
    for (std::size_t i = 0; i < offsets_.size(); ++i) {
      double* block = jacobians[1 + i];
      if (!block) continue;
      const int j = offsets_[i];
      block[0] = row_x[j];
      block[1] = row_x[j + 1];
      block[2] = row_y[j];
      block[3] = row_y[j + 1];
    }
    return true;
  }

 private:
  const mrcal_lensmodel_t* lensmodel_;
  int num_intrinsics_;
  Eigen::Vector3d point_;
  Eigen::Vector2d pixel_;
  std::vector<int> offsets_;
};

// The control points (offsets of their x value in the intrinsics) that move the pixel of p.
std::vector<int> control_points_weighing(const mrcal_lensmodel_t& lensmodel,
                                         const Eigen::VectorXd& intrinsics,
                                         const Eigen::Vector3d& p) {
  const int n = static_cast<int>(intrinsics.size());
  std::vector<double> gradient(2 * n);
  const mrcal_point3_t point = {{p.x(), p.y(), p.z()}};
  mrcal_point2_t q;
  std::set<int> offsets;
  if (!mrcal_project(&q, nullptr, gradient.data(), &point, 1, &lensmodel, intrinsics.data()))
    return {};
  for (int j = kCoreSize; j < n; ++j)
    if (gradient[j] != 0 || gradient[n + j] != 0) offsets.insert(j - (j - kCoreSize) % 2);
  return {offsets.begin(), offsets.end()};
}

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Andrew's monotone chain; the outline is closed, its first point repeated at the end.
std::vector<Eigen::Vector2d> closed_convex_hull(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (points.size() < 3) return points;
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, upper_start = k + 1; i-- > 0;) {
    while (k >= upper_start && cross(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k);
  return hull;
}

}  // namespace

std::vector<PixelRay> valid_pixel_rays(const camera::CatadioptricCamera& camera, double step_px) {
  if (!(step_px > 0) || !std::isfinite(step_px))
    throw std::invalid_argument("the grid step must be a positive number of pixels");
  const Eigen::Vector2d centre((camera.image_width() - 1) / 2.0, (camera.image_height() - 1) / 2.0);
  const int half_columns = static_cast<int>(std::floor((centre.x() + 0.5) / step_px));
  const int half_rows = static_cast<int>(std::floor((centre.y() + 0.5) / step_px));
  std::vector<PixelRay> rays;
  for (int row = -half_rows; row <= half_rows; ++row) {
    for (int column = -half_columns; column <= half_columns; ++column) {
      PixelRay ray;
      ray.pixel = centre + step_px * Eigen::Vector2d(column, row);
      if (camera.in_image(ray.pixel) && camera.unproject(ray.pixel, &ray.origin, &ray.direction))
        rays.push_back(ray);
    }
  }
  return rays;
}

bool CentralMrcalModel::project(const Eigen::Vector3d& X_C, Eigen::Vector2d* pixel) const {
  return project_in_model_frame(camera::mrcal_lensmodel_named(lensmodel), intrinsics,
                                R_model_from_C * X_C + t_model_from_C, pixel);
}

bool CentralMrcalModel::project_direction(const Eigen::Vector3d& direction_C,
                                          Eigen::Vector2d* pixel) const {
  return project_in_model_frame(camera::mrcal_lensmodel_named(lensmodel), intrinsics,
                                R_model_from_C * direction_C, pixel);
}

CentralMrcalModel fit_central_mrcal_model(const camera::CatadioptricCamera& camera,
                                          const std::vector<PixelRay>& rays,
                                          const CentralFitSettings& settings) {
  if (!(settings.distance_m > 0) || !std::isfinite(settings.distance_m))
    throw std::invalid_argument("the distance must be a positive number of metres");
  if (settings.knots < 4 || settings.knots > 100)
    throw std::invalid_argument("the spline needs 4 to 100 control points per axis");
  const int knots = settings.knots;
  // Each control point's patch needs samples; fewer than this leaves the spline undetermined.
  const std::size_t min_rays = 4 * static_cast<std::size_t>(knots) * knots;
  if (rays.size() < min_rays)
    throw std::invalid_argument(std::to_string(rays.size()) + " valid pixels, " +
                                std::to_string(min_rays) + " needed for " + std::to_string(knots) +
                                "x" + std::to_string(knots) + " control points: use a finer grid");

  CentralMrcalModel model;
  model.image_width = camera.image_width();
  model.image_height = camera.image_height();
  std::vector<Eigen::Vector2d> pixels;
  for (const PixelRay& ray : rays) pixels.push_back(ray.pixel);
  model.valid_region = closed_convex_hull(std::move(pixels));
  const Eigen::Matrix3d half_turn_about_x = Eigen::Vector3d(1, -1, -1).asDiagonal();
  model.R_model_from_C = half_turn_about_x * camera.mirror_pose().rotation().transpose();
  model.t_model_from_C = -model.R_model_from_C * point_nearest_to(rays);

  std::vector<Eigen::Vector3d> points;
  points.reserve(rays.size());
  double widest_angle = 0;
  for (const PixelRay& ray : rays) {
    points.push_back(model.R_model_from_C * (ray.origin + settings.distance_m * ray.direction) +
                     model.t_model_from_C);
    const Eigen::Vector3d& p = points.back();
    widest_angle = std::max(widest_angle, std::atan2(p.head<2>().norm(), p.z()));
  }
  const double widest_angle_deg = widest_angle * 180 / kPi;
  if (widest_angle_deg > kWidestAngleDeg)
    throw std::invalid_argument(
        "the field reaches " + io::format_double(std::round(widest_angle_deg)) +
        " degrees from the mirror's axis; a stereographic model takes at most " +
        io::format_double(kWidestAngleDeg));
  const int fov_x_deg = static_cast<int>(std::ceil(2 * widest_angle_deg)) + kFovMarginDeg;
  model.lensmodel = "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=" + std::to_string(knots) +
                    "_Ny=" + std::to_string(knots) + "_fov_x_deg=" + std::to_string(fov_x_deg);
  const mrcal_lensmodel_t lensmodel = camera::mrcal_lensmodel_named(model.lensmodel);
  const int num_intrinsics = mrcal_lensmodel_num_params(&lensmodel);

  // Start from the plain stereographic model, the spline flat.
  std::vector<double> ux, uy, qx, qy;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const Eigen::Vector2d u = stereographic(points[i]);
    ux.push_back(u.x());
    uy.push_back(u.y());
    qx.push_back(rays[i].pixel.x());
    qy.push_back(rays[i].pixel.y());
  }
  const Eigen::Vector2d fx_cx = fit_line(ux, qx), fy_cy = fit_line(uy, qy);
  model.intrinsics = Eigen::VectorXd::Zero(num_intrinsics);
  model.intrinsics.head<kCoreSize>() << fx_cx[0], fy_cy[0], fx_cx[1], fy_cy[1];
  if (!model.intrinsics.allFinite() || fx_cx[0] == 0 || fy_cy[0] == 0)
    throw std::invalid_argument("the rays give no stereographic starting model");

  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  double* core = model.intrinsics.data();
  std::set<int> used_offsets;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    std::vector<int> offsets = control_points_weighing(lensmodel, model.intrinsics, points[i]);
    std::vector<double*> blocks{core};
    for (int offset : offsets) {
      blocks.push_back(model.intrinsics.data() + offset);
      used_offsets.insert(offset);
    }
    problem.AddResidualBlock(new SplinedProjectionResidual(&lensmodel, num_intrinsics, points[i],
                                                           rays[i].pixel, std::move(offsets)),
                             nullptr, blocks);
  }
  const double focal = std::sqrt(std::abs(fx_cx[0] * fy_cy[0]));
  const Eigen::Matrix2d regularization = kRegularization * focal * Eigen::Matrix2d::Identity();
  for (int offset : used_offsets)
    problem.AddResidualBlock(new ceres::NormalPrior(regularization, Eigen::Vector2d::Zero()),
                             nullptr, model.intrinsics.data() + offset);
  // Scaling f and the stereographic coordinates with the spline's output inversely changes no
  // pixel: the core stays the plain stereographic fit, and the spline is the correction to it.
  problem.SetParameterBlockConstant(core);

  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-12;
  options.gradient_tolerance = 1e-12;
  options.parameter_tolerance = 1e-10;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable() || !model.intrinsics.allFinite())
    throw std::runtime_error("the fit of the mrcal model failed: " + summary.message);
  return model;
}

ReprojectionError reprojection_error(const CentralMrcalModel& model,
                                     const std::vector<PixelRay>& rays, double distance_m) {
  ReprojectionError error;
  error.distance_m = distance_m;
  double sum_squares = 0;
  for (const PixelRay& ray : rays) {
    Eigen::Vector2d pixel;
    const bool projected = std::isinf(distance_m)
                               ? model.project_direction(ray.direction, &pixel)
                               : model.project(ray.origin + distance_m * ray.direction, &pixel);
    if (!projected) {
      ++error.num_failed;
      continue;
    }
    const double distance_px = (pixel - ray.pixel).norm();
    ++error.num_points;
    sum_squares += distance_px * distance_px;
    error.worst_px = std::max(error.worst_px, distance_px);
  }
  if (error.num_points > 0) error.rms_px = std::sqrt(sum_squares / error.num_points);
  return error;
}

}  // namespace omnisfm::calib
