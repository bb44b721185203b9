#include "omnisfm/calib/calibration_problem.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "omnisfm/camera/shared_camera.h"
#include "omnisfm/core/solver_threads.h"
#include "pose_jacobian.h"

namespace omnisfm::calib {
namespace {

using camera::SharedCamera;

class ProjectionResidual : public ceres::CostFunction {
 public:
  ProjectionResidual(const SharedCamera* camera, const Eigen::Vector3d& point,
                     const Eigen::Vector2d& pixel)
      : camera_(camera), point_(point), pixel_(pixel) {
    set_num_residuals(2);
    mutable_parameter_block_sizes()->push_back(camera->camera().num_params());
    mutable_parameter_block_sizes()->push_back(6);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    if (!camera_->valid()) return false;
    const auto& camera = camera_->camera();
    const int n = camera.num_params();
    const bool want_pose = jacobians && jacobians[1];
    const bool want_camera = jacobians && jacobians[0];
    Eigen::Matrix<double, 3, 6> J_pose;
    const Eigen::Vector3d X = transform_point(parameters[1], point_, want_pose ? &J_pose : nullptr);
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 3> J_X;
    thread_local camera::ParamsJacobian J_params;
    if (!camera.project(X, &pixel, want_pose ? &J_X : nullptr, want_camera ? &J_params : nullptr))
      return false;
    residuals[0] = pixel.x() - pixel_.x();
    residuals[1] = pixel.y() - pixel_.y();
    if (want_camera)
      Eigen::Map<Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>>(jacobians[0], 2, n) =
          J_params;
    if (want_pose) {
      Eigen::Map<Eigen::Matrix<double, 2, 6, Eigen::RowMajor>> J_pose_out(jacobians[1]);
      J_pose_out = J_X * J_pose;
    }
    return true;
  }

 private:
  const SharedCamera* camera_;
  Eigen::Vector3d point_;
  Eigen::Vector2d pixel_;
};

// Reports the solver's progress as an RMS residual in pixels.
class ProgressCallback : public ceres::IterationCallback {
 public:
  ProgressCallback(const std::function<void(int, double)>& report, int num_residual_blocks,
                   int iterations_before)
      : report_(report), num_residuals_(2 * num_residual_blocks), before_(iterations_before) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    report_(before_ + summary.iteration, std::sqrt(2 * summary.cost / std::max(1, num_residuals_)));
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(int, double)>& report_;
  int num_residuals_, before_;
};

struct Observation {
  int view, index;
  bool outlier = false;
  bool unprojectable_at_start = false;  // until the solve has moved the camera
};

bool residual_of(const camera::CatadioptricCamera& camera, const CalibrationView& view,
                 const double* pose, int index, Eigen::Vector2d* residual) {
  Eigen::Vector2d pixel;
  if (!camera.project(transform_point(pose, view.points[index], nullptr), &pixel)) return false;
  *residual = pixel - view.pixels[index];
  return true;
}

}  // namespace

std::vector<bool> estimate_mask(const camera::CatadioptricCamera& camera,
                                const std::vector<std::string>& groups) {
  const int n = camera.num_params(), ni = camera.shape_param_offset();
  const int shape_end = camera.pose_param_offset();
  const bool has_core = camera.inner().kind() != camera::InnerKind::kMrcal || ni >= 4;
  std::vector<bool> mask(n, false);
  for (const auto& g : groups) {
    if (g == "mirror-pose") {
      for (int i = shape_end; i < n; ++i) mask[i] = true;
    } else if (g == "mirror-shape") {
      for (int i = ni; i < shape_end; ++i) mask[i] = true;
    } else if (g == "intrinsics") {
      for (int i = 0; i < std::min(has_core ? 4 : 0, ni); ++i) mask[i] = true;
    } else if (g == "distortion") {
      for (int i = 4; i < ni; ++i) mask[i] = true;
    } else if (g == "all") {
      std::fill(mask.begin(), mask.end(), true);
    } else {
      throw std::invalid_argument("unknown parameter group '" + g +
                                  "' (expected mirror-pose, mirror-shape, intrinsics, "
                                  "distortion or all)");
    }
  }
  return mask;
}

namespace {

// The solver's options for a calibration of `num_views` views and `residuals` residuals.
ceres::Solver::Options calibration_solver_options(const CalibrationSettings& settings,
                                                  std::size_t num_views, std::size_t residuals) {
  ceres::Solver::Options options;
  options.linear_solver_type = num_views > 20 ? ceres::SPARSE_SCHUR : ceres::DENSE_SCHUR;
  options.max_num_iterations = settings.max_iterations;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  options.gradient_tolerance = 1e-12;
  options.num_threads = core::solver_threads(settings.threads, residuals);
  options.logging_type = ceres::SILENT;
  return options;
}

// One pass of the outlier rejection after a solve whose cost was `final_cost` over `used`
// observations: what lies beyond the threshold (in sigmas of the inliers' residuals) becomes an
// outlier, and what the starting guess could not project comes back once the solved camera
// projects it within the threshold. Returns how many changed.
int reject_outliers(const camera::CatadioptricCamera& camera,
                    const std::vector<CalibrationView>& views,
                    const std::vector<Eigen::Matrix<double, 6, 1>>& poses, double final_cost,
                    int used, int num_unknowns, const CalibrationSettings& settings,
                    std::vector<Observation>* observations) {
  double sum_squares = 2 * final_cost;
  if (settings.cauchy_scale_px > 0) {  // the solver's cost is the robust one: use the squares
    sum_squares = 0;
    for (const auto& o : *observations) {
      Eigen::Vector2d r;
      if (!o.outlier && residual_of(camera, views[o.view], poses[o.view].data(), o.index, &r))
        sum_squares += r.squaredNorm();
    }
  }
  const double sigma = std::sqrt(sum_squares / std::max(1, 2 * used - num_unknowns));
  int changed = 0;
  for (auto& o : *observations) {
    Eigen::Vector2d r;
    const bool beyond =
        !residual_of(camera, views[o.view], poses[o.view].data(), o.index, &r) ||
        r.cwiseAbs().maxCoeff() > settings.outlier_threshold_sigma * sigma;
    if (!o.outlier && beyond) {
      o.outlier = true;
      ++changed;
    } else if (o.outlier && o.unprojectable_at_start && !beyond) {
      o.outlier = o.unprojectable_at_start = false;
      ++changed;
    }
  }
  return changed;
}

// The residuals and their figures (RMS overall and per view, the worst, sigma) into `report`.
void report_residuals(const camera::CatadioptricCamera& camera,
                      const std::vector<CalibrationView>& views,
                      const std::vector<Eigen::Matrix<double, 6, 1>>& poses,
                      const std::vector<Observation>& observations, int num_unknowns,
                      CalibrationReport* report) {
  report->view_rms_px.assign(views.size(), 0.0);
  std::vector<int> view_count(views.size(), 0);
  double sum2 = 0;
  int inliers = 0;
  for (const auto& o : observations) {
    ObservationResidual r{o.view, o.index, {NAN, NAN}, o.outlier};
    residual_of(camera, views[o.view], poses[o.view].data(), o.index, &r.residual);
    report->residuals.push_back(r);
    if (o.outlier) {
      ++report->num_outliers;
      continue;
    }
    const double e2 = r.residual.squaredNorm();
    sum2 += e2;
    ++inliers;
    report->view_rms_px[o.view] += e2;
    ++view_count[o.view];
    report->worst_px = std::max(report->worst_px, std::sqrt(e2));
  }
  report->num_observations = static_cast<int>(observations.size());
  report->rms_px = std::sqrt(sum2 / std::max(1, 2 * inliers));
  for (size_t v = 0; v < views.size(); ++v)
    report->view_rms_px[v] = std::sqrt(report->view_rms_px[v] / std::max(1, 2 * view_count[v]));
  report->residual_sigma_px = std::sqrt(sum2 / std::max(1, 2 * inliers - num_unknowns));
}

// Covariance of the camera parameters, the poses marginalised: the camera block of
// sigma^2 (J^T J)^-1 over all unknowns (the free parameters, then 6 per view), from the inliers.
void report_covariance(const camera::CatadioptricCamera& camera,
                       const std::vector<CalibrationView>& views,
                       const std::vector<Eigen::Matrix<double, 6, 1>>& poses,
                       const std::vector<Observation>& observations,
                       const std::vector<int>& free_params, CalibrationReport* report) {
  const int m = static_cast<int>(free_params.size());
  if (m == 0) return;
  const int num_unknowns = m + 6 * static_cast<int>(views.size());
  int inliers = 0;
  for (const auto& o : observations) inliers += o.outlier ? 0 : 1;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * inliers, num_unknowns);
  camera::ParamsJacobian J_params;
  int row = 0;
  for (const auto& o : observations) {
    if (o.outlier) continue;
    Eigen::Matrix<double, 3, 6> J_pose;
    const Eigen::Vector3d X =
        transform_point(poses[o.view].data(), views[o.view].points[o.index], &J_pose);
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 3> J_X;
    camera.project(X, &pixel, &J_X, &J_params);
    for (int c = 0; c < m; ++c) J.block<2, 1>(row, c) = J_params.col(free_params[c]);
    J.block<2, 6>(row, m + 6 * o.view) = J_X * J_pose;
    row += 2;
  }
  // Columns scaled to unit length first: metres, radians and pixels differ by orders of
  // magnitude, and the rank test must see the geometry, not the units.
  const Eigen::VectorXd scale = J.colwise().norm().cwiseMax(1e-300).cwiseInverse();
  const Eigen::MatrixXd Js = J * scale.asDiagonal();
  const Eigen::MatrixXd H = Js.transpose() * Js;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(H);
  lu.setThreshold(1e-12);
  if (lu.rank() < H.rows()) {
    report->converged = false;
    report->message = "degenerate geometry: the estimated parameters are not all observable";
  } else {
    const Eigen::MatrixXd covariance = scale.asDiagonal() * lu.inverse() * scale.asDiagonal();
    report->joint_covariance = report->residual_sigma_px * report->residual_sigma_px *
                               (covariance + covariance.transpose()) / 2;
    report->covariance = report->joint_covariance.topLeftCorner(m, m);
  }
}

}  // namespace

CalibrationReport calibrate(camera::CatadioptricCamera* camera, std::vector<CalibrationView>* views,
                            const CalibrationSettings& settings) {
  const int n = camera->num_params();
  if (static_cast<int>(settings.estimate.size()) != n)
    throw std::invalid_argument("calibrate: the estimate mask does not match the camera");
  std::vector<int> free_params;
  for (int i = 0; i < n; ++i)
    if (settings.estimate[i]) free_params.push_back(i);
  const int num_unknowns = static_cast<int>(free_params.size() + 6 * views->size());

  std::vector<Eigen::Matrix<double, 6, 1>> poses;
  std::vector<Observation> observations;
  for (size_t v = 0; v < views->size(); ++v) {
    poses.push_back(core::pose_vector_of((*views)[v].cam_from_object));
    for (size_t i = 0; i < (*views)[v].points.size(); ++i)
      observations.push_back({static_cast<int>(v), static_cast<int>(i)});
  }
  if (2 * static_cast<int>(observations.size()) <= num_unknowns)
    throw std::invalid_argument("calibrate: " + std::to_string(observations.size()) +
                                " observations cannot determine " + std::to_string(num_unknowns) +
                                " unknowns");

  Eigen::VectorXd params = camera->params();
  CalibrationReport report;
  for (const int i : free_params) report.estimated_names.push_back(camera->param_names()[i]);

  // What the starting guess cannot project at all is an outlier from the start.
  for (auto& o : observations) {
    Eigen::Vector2d r;
    o.outlier = !residual_of(*camera, (*views)[o.view], poses[o.view].data(), o.index, &r);
    o.unprojectable_at_start = o.outlier;
  }

  for (int round = 0; round <= settings.max_outlier_rounds; ++round) {
    ceres::Problem::Options problem_options;
    auto shared = std::make_unique<SharedCamera>(*camera, params.data());
    problem_options.evaluation_callback = shared.get();
    ceres::Problem problem(problem_options);
    int used = 0;
    for (const auto& o : observations) {
      if (o.outlier) continue;
      const auto& view = (*views)[o.view];
      problem.AddResidualBlock(
          new ProjectionResidual(shared.get(), view.points[o.index], view.pixels[o.index]),
          settings.cauchy_scale_px > 0 ? new ceres::CauchyLoss(settings.cauchy_scale_px) : nullptr,
          params.data(), poses[o.view].data());
      ++used;
    }
    if (2 * used <= num_unknowns) {
      report.message = "too few observations remain after outlier rejection";
      return report;
    }
    if (free_params.empty()) {
      problem.SetParameterBlockConstant(params.data());
    } else if (static_cast<int>(free_params.size()) < n) {
      std::vector<int> fixed;
      for (int i = 0; i < n; ++i)
        if (!settings.estimate[i]) fixed.push_back(i);
      problem.SetManifold(params.data(), new ceres::SubsetManifold(n, fixed));
    }

    ceres::Solver::Options options =
        calibration_solver_options(settings, views->size(), 2 * static_cast<std::size_t>(used));
    ProgressCallback progress(settings.progress, used, report.iterations);
    if (settings.progress) options.callbacks.push_back(&progress);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    report.iterations += static_cast<int>(summary.iterations.size());
    report.converged = summary.termination_type == ceres::CONVERGENCE;
    report.message = summary.message;
    if (!summary.IsSolutionUsable()) return report;
    if (!camera->set_params(params)) {
      report.converged = false;
      report.message = "the solution left the camera model's valid domain";
      return report;
    }

    // Reject what lies beyond the threshold; stop when nothing changes.
    if (round == settings.max_outlier_rounds) break;
    const int changed = reject_outliers(*camera, *views, poses, summary.final_cost, used,
                                        num_unknowns, settings, &observations);
    if (changed == 0) break;
  }

  report_residuals(*camera, *views, poses, observations, num_unknowns, &report);
  for (size_t v = 0; v < views->size(); ++v)
    (*views)[v].cam_from_object = core::isometry_of(poses[v].data());

  report_covariance(*camera, *views, poses, observations, free_params, &report);
  return report;
}

}  // namespace omnisfm::calib
