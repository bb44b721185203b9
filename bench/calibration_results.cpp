// Calibration results for the README, measured in one run:
//   - the real checkerboard sets vmr and paracatadioptric (their published corners) and Kaidan
//     (no corners published: detected as `omnisfm detect-corners` detects them, a 7 x 5 block of
//     its larger boards): omnisfm's noncentral model, calibrated from the shipped starting
//     guesses, next to OpenCV's cv::omnidir::calibrate (Mei's unified model) and mrcal's splined
//     stereographic model (bench/mrcal_cross_validation.py, run with Debian's python3-mrcal) on
//     the same corners: RMS over all views and leave-one-view-out RMS (Kaidan also from the
//     generic conic start of calibrate --mirror conic); and the same on a rig none
//     of those shows, the 15 views' corners of opencv_contrib's omnidir tutorial
//     (tests/data/opencv-omnidir);
//   - the paper's method on the simulated lab (0.1 px noise): the mirror's errors.
// Not a unit test: it prints a table. Usage:
//   calibration_results [REAL_DATA_DIR]    (default: ../shared/data/real-catadioptric beside the
//                                           source tree)
// Residuals are given per coordinate (mrcal's and omnisfm's convention) and, in brackets, as the
// RMS of the residual vectors' lengths (OpenCV's figure, sqrt(2) times larger).

#include <ceres/ceres.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/calib3d.hpp>
#include <opencv2/ccalib/omnidir.hpp>
#include <opengv/absolute_pose/CentralAbsoluteAdapter.hpp>
#include <opengv/absolute_pose/methods.hpp>
#include <opengv/sac/Ransac.hpp>
#include <opengv/sac_problems/absolute_pose/AbsolutePoseSacProblem.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisfm/calib/board_detection.h"
#include "omnisfm/calib/calibration_views.h"
#include "omnisfm/calib/cross_validation.h"
#include "omnisfm/calib/staged_calibration.h"
#include "omnisfm/calib/starting_camera.h"
#include "omnisfm/camera/camera_kinds.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/checkerboard_files.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/track/image_sequence.h"
#include "real_data_folder.h"

namespace {

using omnisfm::calib::CalibrationView;
namespace fs = std::filesystem;

struct RealSet {
  std::string name, corners, initial_camera;
  std::vector<Eigen::Vector3d> board;
  std::vector<std::string> groups;
  // mrcal_cross_validation.py's board and focal-length guess (stereographic: the picture's edge
  // radius over 2 tan(55 deg), for a rim 20-25 degrees above the horizon).
  std::string mrcal_board;
  double mrcal_focal = 0;
  // Starts of other kinds the set is also calibrated from (calibrate --mirror's generic ones).
  std::vector<std::string> other_starts;
};

struct Fit {
  double rms_px = NAN;        // per coordinate, over the observations counted
  int observations = 0;       // counted
  int views = 0;              // used
  int rejected = 0;           // observations rejected as outliers (omnisfm) or in dropped views
  double loo_rms_px = NAN;    // leave-one-view-out, per coordinate, all held-out observations
  int loo_observations = 0;
  std::string note;
};

std::string both(double rms) {
  char text[64];
  std::snprintf(text, sizeof text, "%.4f (%.4f)", rms, rms * std::sqrt(2.0));
  return text;
}

// --- omnisfm -------------------------------------------------------------------------------------

double rms_of(const std::vector<omnisfm::calib::ObservationResidual>& residuals, bool inliers_only,
              int* count) {
  double sum2 = 0;
  *count = 0;
  for (const auto& r : residuals) {
    if ((inliers_only && r.outlier) || !r.residual.allFinite()) continue;
    sum2 += r.residual.squaredNorm();
    ++*count;
  }
  return std::sqrt(sum2 / std::max(1, 2 * *count));
}

// One calibration of all views, and one per left-out view; with outlier rejection (the default) or
// without (every observation counted, as OpenCV counts them).
Fit omnisfm_fit(const RealSet& set, const std::vector<CalibrationView>& views,
                const std::vector<std::string>& groups, bool reject) {
  const auto initial = omnisfm::io::read_camera_file(set.initial_camera);
  omnisfm::calib::StagedSettings settings;
  settings.groups = groups;
  if (!reject) settings.max_outlier_rounds = 0;
  Fit fit;
  auto camera = initial;
  auto solved = views;
  const auto report = omnisfm::calib::calibrate_in_stages(&camera, &solved, settings);
  fit.rms_px = rms_of(report.final.residuals, true, &fit.observations);
  fit.views = static_cast<int>(views.size());
  fit.rejected = report.final.num_outliers;
  if (!report.final.converged) fit.note = "did not converge: " + report.final.message;

  double sum2 = 0;
  int count = 0, failed = 0;
  for (std::size_t held = 0; held < views.size(); ++held) {
    std::vector<CalibrationView> train;
    for (std::size_t v = 0; v < views.size(); ++v)
      if (v != held) train.push_back(views[v]);
    auto fold_camera = initial;
    const auto fold = omnisfm::calib::calibrate_in_stages(&fold_camera, &train, settings);
    if (!fold.final.converged) ++failed;
    const auto result = omnisfm::calib::evaluate_held_out(fold_camera, {views[held]});
    sum2 += result.rms_px * result.rms_px * 2 * result.num_observations;
    count += result.num_observations;
  }
  fit.loo_rms_px = std::sqrt(sum2 / std::max(1, 2 * count));
  fit.loo_observations = count;
  if (failed) fit.note += " " + std::to_string(failed) + " folds did not converge";
  return fit;
}

// --- OpenCV omnidir (Mei) ------------------------------------------------------------------------

struct MeiModel {
  cv::Matx33d K;
  cv::Matx14d D;
  double xi = 0;
};

struct MeiData {
  std::vector<cv::Mat> object, image;  // CV_64FC3, CV_64FC2 per view
};

MeiData mei_data(const std::vector<CalibrationView>& views) {
  MeiData data;
  for (const auto& view : views) {
    const int n = static_cast<int>(view.points.size());
    cv::Mat object(1, n, CV_64FC3), image(1, n, CV_64FC2);
    for (int i = 0; i < n; ++i) {
      object.at<cv::Vec3d>(i) = {view.points[i].x(), view.points[i].y(), view.points[i].z()};
      image.at<cv::Vec2d>(i) = {view.pixels[i].x(), view.pixels[i].y()};
    }
    data.object.push_back(object);
    data.image.push_back(image);
  }
  return data;
}

double mei_sum_squares(const MeiModel& model, const cv::Mat& object, const cv::Mat& image,
                       const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  cv::Mat projected;
  cv::omnidir::projectPoints(object, projected, rvec, tvec, model.K, model.xi, model.D);
  double sum2 = 0;
  for (int i = 0; i < static_cast<int>(projected.total()); ++i) {
    const cv::Vec2d d = projected.at<cv::Vec2d>(i) - image.at<cv::Vec2d>(i);
    sum2 += d.dot(d);
  }
  return sum2;
}

// Calibrates; returns the indices of the views omnidir kept, and their poses.
std::vector<int> mei_calibrate(const MeiData& data, cv::Size size, MeiModel* model,
                               std::vector<cv::Vec3d>* rvecs, std::vector<cv::Vec3d>* tvecs) {
  cv::Mat K, xi, D, idx;
  std::vector<cv::Mat> r, t;
  cv::omnidir::calibrate(data.object, data.image, size, K, xi, D, r, t, 0,
                         cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 300,
                                          1e-8),
                         idx);
  model->K = K;
  model->D = D;
  model->xi = xi.at<double>(0);
  std::vector<int> kept;
  for (int k = 0; k < static_cast<int>(idx.total()); ++k) {
    kept.push_back(idx.at<int>(k));
    rvecs->push_back(r[k]);
    tvecs->push_back(t[k]);
  }
  return kept;
}

// The unit ray of a pixel under the Mei model: the distortion removed by fixed-point iteration (as
// OpenCV does), then the point lifted to the unit sphere. OpenCV's own undistortPoints picks the
// wrong root of the lifting for xi > 1, as fitted on vmr.
Eigen::Vector3d mei_ray(const MeiModel& model, const cv::Vec2d& pixel) {
  const double fx = model.K(0, 0), fy = model.K(1, 1), s = model.K(0, 1);
  const double cx = model.K(0, 2), cy = model.K(1, 2);
  const double k1 = model.D(0), k2 = model.D(1), p1 = model.D(2), p2 = model.D(3);
  const double py = (pixel[1] - cy) / fy, px = (pixel[0] - cx - s * py) / fx;
  double x = px, y = py;
  for (int i = 0; i < 50; ++i) {
    const double r2 = x * x + y * y, radial = 1 + k1 * r2 + k2 * r2 * r2;
    x = (px - 2 * p1 * x * y - p2 * (r2 + 2 * x * x)) / radial;
    y = (py - p1 * (r2 + 2 * y * y) - 2 * p2 * x * y) / radial;
  }
  const double r2 = x * x + y * y, xi = model.xi;
  const double factor = (xi + std::sqrt(std::max(0.0, 1 + (1 - xi * xi) * r2))) / (1 + r2);
  return Eigen::Vector3d(factor * x, factor * y, factor - xi).normalized();
}

struct MeiReprojection {
  MeiReprojection(const MeiModel& model, const cv::Vec3d& point, const cv::Vec2d& pixel)
      : model_(model), point_(point), pixel_(pixel) {}
  bool operator()(const double* pose, double* residual) const {
    cv::Mat object(1, 1, CV_64FC3), projected;
    object.at<cv::Vec3d>(0) = point_;
    cv::omnidir::projectPoints(object, projected, cv::Vec3d(pose[0], pose[1], pose[2]),
                               cv::Vec3d(pose[3], pose[4], pose[5]), model_.K, model_.xi,
                               model_.D);
    const cv::Vec2d d = projected.at<cv::Vec2d>(0) - pixel_;
    residual[0] = d[0];
    residual[1] = d[1];
    return true;
  }
  MeiModel model_;
  cv::Vec3d point_;
  cv::Vec2d pixel_;
};

// A held-out view's pose with the Mei model fixed: central P3P in RANSAC on the model's rays, then
// the reprojection error minimised. Returns the view's sum of squared residuals, or NaN.
double mei_held_out_sum_squares(const MeiModel& model, const cv::Mat& object, const cv::Mat& image) {
  const int n = static_cast<int>(object.total());
  opengv::bearingVectors_t bearings;
  opengv::points_t points;
  for (int i = 0; i < n; ++i) {
    bearings.push_back(mei_ray(model, image.at<cv::Vec2d>(i)));
    const cv::Vec3d p = object.at<cv::Vec3d>(i);
    points.emplace_back(p[0], p[1], p[2]);
  }
  opengv::absolute_pose::CentralAbsoluteAdapter adapter(bearings, points);
  using Problem = opengv::sac_problems::absolute_pose::AbsolutePoseSacProblem;
  opengv::sac::Ransac<Problem> ransac;
  ransac.sac_model_ = std::make_shared<Problem>(adapter, Problem::KNEIP, false);
  ransac.threshold_ = 1.0 - std::cos(0.02);
  ransac.max_iterations_ = 500;
  if (!ransac.computeModel()) return NAN;
  const opengv::transformation_t world_from_cam = ransac.model_coefficients_;
  const Eigen::Matrix3d R = world_from_cam.leftCols<3>().transpose();
  const Eigen::Vector3d t = -R * world_from_cam.col(3);
  cv::Vec3d rvec;
  cv::Rodrigues(cv::Matx33d(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1),
                            R(2, 2)),
                rvec);
  double pose[6] = {rvec[0], rvec[1], rvec[2], t.x(), t.y(), t.z()};
  ceres::Problem problem;
  for (int i = 0; i < n; ++i) {
    problem.AddResidualBlock(
        new ceres::NumericDiffCostFunction<MeiReprojection, ceres::CENTRAL, 2, 6>(
            new MeiReprojection(model, object.at<cv::Vec3d>(i), image.at<cv::Vec2d>(i))),
        nullptr, pose);
  }
  ceres::Solver::Options options;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-12;
  options.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  return mei_sum_squares(model, object, image, cv::Vec3d(pose[0], pose[1], pose[2]),
                         cv::Vec3d(pose[3], pose[4], pose[5]));
}

Fit omnidir_fit(const std::vector<CalibrationView>& views, cv::Size size) {
  const MeiData data = mei_data(views);
  Fit fit;
  MeiModel model;
  std::vector<cv::Vec3d> rvecs, tvecs;
  const std::vector<int> kept = mei_calibrate(data, size, &model, &rvecs, &tvecs);
  double sum2 = 0;
  for (std::size_t k = 0; k < kept.size(); ++k) {
    sum2 += mei_sum_squares(model, data.object[kept[k]], data.image[kept[k]], rvecs[k], tvecs[k]);
    fit.observations += static_cast<int>(data.object[kept[k]].total());
  }
  fit.rms_px = std::sqrt(sum2 / (2 * fit.observations));
  fit.views = static_cast<int>(kept.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (std::find(kept.begin(), kept.end(), static_cast<int>(v)) == kept.end()) {
      fit.rejected += static_cast<int>(views[v].points.size());
      fit.note += (fit.note.empty() ? "dropped " : ", ") + views[v].name;
    }
  }

  double loo_sum2 = 0;
  int failed = 0;
  for (std::size_t held = 0; held < views.size(); ++held) {
    MeiData train;
    for (std::size_t v = 0; v < views.size(); ++v) {
      if (v == held) continue;
      train.object.push_back(data.object[v]);
      train.image.push_back(data.image[v]);
    }
    MeiModel fold;
    std::vector<cv::Vec3d> r, t;
    mei_calibrate(train, size, &fold, &r, &t);
    const double s = mei_held_out_sum_squares(fold, data.object[held], data.image[held]);
    if (!std::isfinite(s)) {
      ++failed;
      continue;
    }
    loo_sum2 += s;
    fit.loo_observations += static_cast<int>(data.object[held].total());
  }
  fit.loo_rms_px = std::sqrt(loo_sum2 / std::max(1, 2 * fit.loo_observations));
  if (failed) fit.note += (fit.note.empty() ? "" : "; ") + std::to_string(failed) +
                          " held-out views got no pose";
  return fit;
}

// mrcal's splined stereographic model (8 x 6 knots) on the same corners, through
// bench/mrcal_cross_validation.py (mrcal's own calibration tool, and the same leave-one-out).
Fit mrcal_fit(const RealSet& set, cv::Size size) {
  const std::string command =
      "/usr/bin/python3 " + std::string(OMNISFM_SOURCE_DIR) + "/bench/mrcal_cross_validation.py " +
      set.corners + " --imagersize " + std::to_string(size.width) + " " +
      std::to_string(size.height) + " " + set.mrcal_board + " --focal " +
      std::to_string(set.mrcal_focal) + " --flip-x";
  Fit fit;
  FILE* out = popen(command.c_str(), "r");
  if (!out || std::fscanf(out, "views %d rms %lf rejected %d loo_rms %lf observations %d",
                          &fit.views, &fit.rms_px, &fit.rejected, &fit.loo_rms_px,
                          &fit.loo_observations) != 5)
    fit.note = "mrcal_cross_validation.py failed";
  if (out) pclose(out);
  return fit;
}

// --- Report ------------------------------------------------------------------------------------

void print_row(const std::string& set, const std::string& method, const Fit& fit) {
  std::printf("| %-16s | %-64s | %5d | %-15s | %8d | %-15s | %s |\n", set.c_str(), method.c_str(),
              fit.views, both(fit.rms_px).c_str(), fit.rejected, both(fit.loo_rms_px).c_str(),
              fit.note.c_str());
}

// The boards in a folder of images, found as `omnisfm detect-corners` finds them (read as it
// reads them, the mirror on their mean), written to `path` as corners.vnl; returns `path`.
std::string detected_corners(const std::string& folder, cv::Size grid, const std::string& path,
                             omnisfm::calib::MirrorImage* mirror) {
  omnisfm::calib::MeanImage mean;
  omnisfm::track::SequenceFrame frame;
  for (omnisfm::track::ImageSequence images(folder); images.next(&frame);) mean.add(frame.image);
  *mirror = omnisfm::calib::find_mirror_image(mean.mean());
  omnisfm::calib::BoardDetector detector(*mirror, grid);
  std::vector<omnisfm::io::ImageCorners> found;
  for (omnisfm::track::ImageSequence images(folder); images.next(&frame);) {
    found.push_back(omnisfm::calib::image_corners(fs::path(frame.file).filename().string(),
                                                  detector.detect(frame.image)));
  }
  omnisfm::io::write_corners(path, found);
  return path;
}

void real_data(const std::string& root) {
  const std::string share = std::string(OMNISFM_SHARE_DIR) + "/cameras/";
  const std::vector<std::string> groups = {"mirror-pose", "intrinsics", "mirror-shape"};
  omnisfm::calib::MirrorImage kaidan_mirror;
  const std::string kaidan_corners = detected_corners(
      root + "/kaidan", cv::Size(7, 5),
      (fs::temp_directory_path() / ("omnisfm-kaidan-corners-" + std::to_string(getpid()) + ".vnl"))
          .string(),
      &kaidan_mirror);
  // Kaidan's mirror is sold as equiangular; the generic conic start (calibrate --mirror conic)
  // is tried too.
  const std::string kaidan_conic_start =
      (fs::temp_directory_path() / ("omnisfm-kaidan-conic-" + std::to_string(getpid()) + ".ini"))
          .string();
  {
    const auto equiangular = omnisfm::io::read_camera_file(share + "kaidan-initial.ini");
    omnisfm::io::write_camera_file(
        kaidan_conic_start,
        omnisfm::calib::starting_camera(
            kaidan_mirror, equiangular.image_width(), equiangular.image_height(),
            omnisfm::calib::StartingMirror::kConic, omnisfm::calib::StartingInner::kPinhole));
  }
  // A rig none of the shared sets shows, its 15 views' corners from opencv_contrib's omnidir
  // tutorial (tests/data/opencv-omnidir): started from vmr's hand-written start with the image's
  // size and centre, as a user would copy it (calibrate's start-free fit is the same).
  const std::string omnidir_start =
      (fs::temp_directory_path() / ("omnisfm-omnidir-start-" + std::to_string(getpid()) + ".ini"))
          .string();
  {
    auto start = omnisfm::io::read_camera_file(share + "vmr-initial.ini");
    if (start.inner().kind() != omnisfm::camera::InnerKind::kPinhole)
      throw std::runtime_error("vmr-initial.ini: the start assumed a pinhole lens");
    auto lens = static_cast<const omnisfm::camera::PinholeCamera&>(start.inner()).intrinsics();
    lens.cx = 639.5;
    lens.cy = 479.5;
    omnisfm::io::write_camera_file(omnidir_start,
                                   omnisfm::camera::CatadioptricCamera(
                                       std::make_unique<omnisfm::camera::PinholeCamera>(lens),
                                       start.mirror().clone(), start.mirror_pose(), 1280, 960));
  }
  const std::string omnidir_corners =
      (fs::path(OMNISFM_SOURCE_DIR) / "tests/data/opencv-omnidir/tutorial-corners.vnl").string();
  // The Kaidan board's square is not published; 30 mm is assumed, which scales its poses only.
  // The omnidir tutorial's focal length by the rule: its picture's edge at 518 px.
  // mrcal's seeding fails on every fold from the rule's focal length (76 px for its picture's
  // edge at 218 px) and takes 120.
  const std::vector<RealSet> sets = {
      {"vmr", root + "/vmr/corners.vnl", share + "vmr-initial.ini",
       omnisfm::io::read_board(root + "/vmr/board.vnl"), groups,
       "--object-spacing 0.03 --object-width-n 6 --object-height-n 7", 143},
      {"paracatadioptric", root + "/paracatadioptric/corners.vnl",
       share + "paracatadioptric-initial.ini",
       omnisfm::io::read_board(root + "/paracatadioptric/board.vnl"), groups,
       "--object-spacing 0.041 --object-width-n 6 --object-height-n 8", 124},
      {"kaidan",
       kaidan_corners,
       share + "kaidan-initial.ini",
       omnisfm::io::regular_board(0.03, 7, 5),
       groups,
       "--object-spacing 0.03 --object-width-n 7 --object-height-n 5",
       120,
       {kaidan_conic_start}},
      {"omnidir tutorial", omnidir_corners, omnidir_start, omnisfm::io::regular_board(0.2, 6, 9),
       groups, "--object-spacing 0.2 --object-width-n 6 --object-height-n 9", 181}};
  std::printf("Real checkerboards (%s).\nRMS per coordinate (in brackets: RMS of the residual "
              "vectors' lengths, OpenCV's figure), pixels.\n\n",
              root.c_str());
  std::printf("| %-16s | %-64s | %5s | %-15s | %8s | %-15s | %s |\n", "set", "model", "views",
              "RMS", "rejected", "leave-1-out", "note");
  std::printf("|%s|%s|%s|%s|%s|%s|%s|\n", std::string(18, '-').c_str(),
              std::string(66, '-').c_str(), std::string(7, '-').c_str(),
              std::string(17, '-').c_str(), std::string(10, '-').c_str(),
              std::string(17, '-').c_str(), std::string(6, '-').c_str());
  for (const RealSet& set : sets) {
    const auto start = std::chrono::steady_clock::now();
    const auto camera = omnisfm::io::read_camera_file(set.initial_camera);
    const auto views = omnisfm::calib::board_views(omnisfm::io::read_corners(set.corners),
                                                   set.board, set.corners, "the board");
    const std::string model = std::string("omnisfm ") +
                              omnisfm::camera::name_of(camera.mirror().kind()) + "+" +
                              omnisfm::camera::name_of(camera.inner().kind());
    print_row(set.name, model + ", pose+intrinsics+shape", omnisfm_fit(set, views, groups, false));
    print_row(set.name, model + ", pose+intrinsics+shape, 4-sigma rej.",
              omnisfm_fit(set, views, groups, true));
    // An orthographic camera has no distortion to add.
    if (camera.inner().kind() == omnisfm::camera::InnerKind::kPinhole)
      print_row(set.name, model + ", all (+ distortion)", omnisfm_fit(set, views, {"all"}, false));
    for (const std::string& other : set.other_starts) {
      RealSet from_other = set;
      from_other.initial_camera = other;
      const auto start = omnisfm::io::read_camera_file(other);
      const std::string kinds = std::string("omnisfm ") +
                                omnisfm::camera::name_of(start.mirror().kind()) + "+" +
                                omnisfm::camera::name_of(start.inner().kind()) +
                                " (generic start), pose+intrinsics+shape";
      print_row(set.name, kinds, omnisfm_fit(from_other, views, groups, false));
      print_row(set.name, kinds + ", 4-sigma rej.", omnisfm_fit(from_other, views, groups, true));
    }
    print_row(set.name, "OpenCV omnidir (Mei, 10 parameters)",
              omnidir_fit(views, cv::Size(camera.image_width(), camera.image_height())));
    print_row(set.name, "mrcal splined stereographic (8x6 knots, 300 deg)",
              mrcal_fit(set, cv::Size(camera.image_width(), camera.image_height())));
    std::fprintf(stderr, "%s: %.1f s\n", set.name.c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  fs::remove(kaidan_corners);
  fs::remove(kaidan_conic_start);
  fs::remove(omnidir_start);
  std::printf(
      "\nomnisfm starts from share/omnisfm/cameras/<set>-initial.ini (the omnidir tutorial from "
      "vmr's,\nits image's size and centre) and estimates the groups named (less what "
      "parameter_gauge.h holds); 'rejection': residuals beyond 4 sigma "
      "rejected, the RMS over\nthe rest. Leave-one-out: each view left out in turn, its pose "
      "solved with the camera fixed,\nall its observations counted. OpenCV: omnidir::calibrate, "
      "flags 0, on the same corners; it drops\nviews its initialisation cannot use. mrcal: "
      "mrcal-calibrate-cameras on the corners mirrored left to right (a\ncatadioptric image is a "
      "mirror image, which no central mrcal model is), with its own outlier\nrejection, "
      "regularisation and board warp; the same leave-one-out.\n");
}

void lab() {
  // The paper's method on `omnisfm simulate --scenario lab --noise 0.1`: the nominal aligned rig,
  // the mirror's 5 parameters and one pose per image; poses from OpenGV, no guess.
  constexpr int kSeeds = 100;
  double worst_t = 0, worst_r = 0, sum_t = 0, sum_r = 0;
  Eigen::VectorXd spread2 = Eigen::VectorXd::Zero(5);
  int converged = 0;
  double seed1_t = 0, seed1_rx = 0, seed1_ry = 0, seed1_rms = 0;
  for (int seed = 1; seed <= kSeeds; ++seed) {
    omnisfm::sim::SimulationOptions options;
    options.scenario = "lab";
    options.seed = seed;
    options.tracking_noise_px = 0.1;
    const auto dataset = omnisfm::sim::simulate(options);
    auto camera = dataset.camera;
    camera.set_mirror_pose({});
    std::vector<omnisfm::io::TargetObservationRow> rows;
    for (const auto& o : dataset.target_observations) rows.push_back({o.image, o.target, o.pixel, 0});
    std::map<int, Eigen::Vector3d> targets;
    for (std::size_t t = 0; t < dataset.surveyed_targets.size(); ++t)
      targets[static_cast<int>(t)] = dataset.surveyed_targets[t];
    auto views = omnisfm::calib::target_views(targets, rows, "observations");
    const auto report = omnisfm::calib::calibrate_in_stages(&camera, &views, {});
    if (!report.final.converged) continue;
    ++converged;
    const auto truth = dataset.camera.mirror_pose(), found = camera.mirror_pose();
    const double t_mm = (found.translation() - truth.translation()).norm() * 1e3;
    const double r_deg =
        std::max(std::abs(found.rx - truth.rx), std::abs(found.ry - truth.ry)) * 180 / M_PI;
    worst_t = std::max(worst_t, t_mm);
    worst_r = std::max(worst_r, r_deg);
    sum_t += t_mm;
    sum_r += r_deg;
    const Eigen::Matrix<double, 5, 1> error = found.as_vector() - truth.as_vector();
    spread2 += error.cwiseQuotient(report.final.covariance.diagonal().cwiseSqrt()).cwiseAbs2();
    if (seed == 1) {
      seed1_t = t_mm;
      seed1_rx = (found.rx - truth.rx) * 180 / M_PI;
      seed1_ry = (found.ry - truth.ry) * 180 / M_PI;
      seed1_rms = report.final.rms_px;
    }
  }
  const Eigen::VectorXd spread = (spread2 / std::max(1, converged)).cwiseSqrt();
  std::printf("\nSimulated lab, 0.1 px noise, 44 targets in 4 images, the paper's method "
              "(mirror-pose):\n\n");
  std::printf("| %-36s | %s |\n", "figure", "value");
  std::printf("|%s|%s|\n", std::string(38, '-').c_str(), std::string(40, '-').c_str());
  std::printf("| %-36s | %.3f mm, rx %+.4f deg, ry %+.4f deg, RMS %.3f px |\n",
              "seed 1 (omnisfm simulate default)", seed1_t, seed1_rx, seed1_ry, seed1_rms);
  std::printf("| %-36s | %d of %d |\n", "seeds converged", converged, kSeeds);
  std::printf("| %-36s | mean %.3f mm, worst %.3f mm |\n", "translation error", sum_t / converged,
              worst_t);
  std::printf("| %-36s | mean %.4f deg, worst %.4f deg |\n", "rotation error (max of rx, ry)",
              sum_r / converged, worst_r);
  std::printf("| %-36s | rx %.2f ry %.2f tx %.2f ty %.2f tz %.2f |\n",
              "spread of error / reported sigma", spread[0], spread[1], spread[2], spread[3],
              spread[4]);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string root = argc > 1 ? argv[1] : omnisfm::test::real_data_folder(OMNISFM_SOURCE_DIR);
  if (fs::is_directory(root)) {
    real_data(root);
  } else {
    std::printf("no real data at %s: skipped\n", root.c_str());
  }
  lab();
  return 0;
}
