// The paper's calibration: the mirror-to-camera transform and the camera's poses from images of
// surveyed targets, starting from the nominal aligned design with no pose guess.

#include <glog/logging.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "omnisfm/calib/calibration_problem.h"
#include "omnisfm/calib/pose_initialization.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::calib {
namespace {

struct LabCalibration {
  camera::CatadioptricCamera truth, estimate;
  CalibrationReport report;
  Eigen::Isometry3d true_cam_from_world, cam_from_world;
};

LabCalibration calibrate_lab(std::uint64_t seed, double noise_px) {
  sim::SimulationOptions options;
  options.scenario = "lab";
  options.seed = seed;
  options.tracking_noise_px = noise_px;
  const sim::Dataset lab = sim::simulate(options);

  // The nominal design: the same rig, aligned.
  camera::CatadioptricCamera nominal = lab.camera;
  nominal.set_mirror_pose({});
  std::map<int, CalibrationView> by_image;
  for (const auto& o : lab.target_observations) {
    by_image[o.image].name = "image " + std::to_string(o.image);
    by_image[o.image].points.push_back(lab.surveyed_targets[o.target]);
    by_image[o.image].pixels.push_back(o.pixel);
  }
  std::vector<CalibrationView> views;
  for (auto& [image, view] : by_image) {
    EXPECT_TRUE(initial_pose(nominal, view.points, view.pixels, &view.cam_from_object));
    views.push_back(view);
  }
  CalibrationSettings settings;
  settings.estimate = estimate_mask(nominal, {"mirror-pose"});
  LabCalibration result{lab.camera, nominal, {}, lab.world_from_cam[0].inverse(), {}};
  result.report = calibrate(&result.estimate, &views, settings);
  result.cam_from_world = views[0].cam_from_object;
  return result;
}

TEST(TargetCalibration, RecoversTheMirrorTransformFromTheNominalDesign) {
  const LabCalibration c = calibrate_lab(1, 0.1);
  ASSERT_TRUE(c.report.converged) << c.report.message;
  const auto& truth = c.truth.mirror_pose();
  const auto& found = c.estimate.mirror_pose();
  EXPECT_LT((found.translation() - truth.translation()).norm(), 0.5e-3);
  EXPECT_LT(std::abs(found.rx - truth.rx) * 180 / M_PI, 0.05);
  EXPECT_LT(std::abs(found.ry - truth.ry) * 180 / M_PI, 0.05);
  EXPECT_LT((c.cam_from_world.translation() - c.true_cam_from_world.translation()).norm(), 2e-3);
  EXPECT_NEAR(c.report.rms_px, 0.1, 0.02);
  EXPECT_EQ(c.report.estimated_names.size(), 5u);
  ASSERT_EQ(c.report.covariance.rows(), 5);
}

// glog's level is the program's: the calibration leaves it as it found it.
TEST(TargetCalibration, LeavesGlogAsTheProgramSetIt) {
  const int program_level = FLAGS_minloglevel;
  FLAGS_minloglevel = google::GLOG_INFO;
  const LabCalibration c = calibrate_lab(2, 0.1);
  EXPECT_EQ(FLAGS_minloglevel, google::GLOG_INFO);
  FLAGS_minloglevel = program_level;
  EXPECT_TRUE(c.report.converged) << c.report.message;
}

TEST(TargetCalibration, ReportedSigmasMatchTheSpreadOfTheErrors) {
  // Over many seeds, the normalised errors (error / reported sigma) have unit spread when the
  // covariance is honest.
  constexpr int kSeeds = 100;
  Eigen::VectorXd sum2 = Eigen::VectorXd::Zero(5);
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const LabCalibration c = calibrate_lab(seed, 0.1);
    ASSERT_TRUE(c.report.converged) << seed;
    const Eigen::Matrix<double, 5, 1> error =
        c.estimate.mirror_pose().as_vector() - c.truth.mirror_pose().as_vector();
    const Eigen::VectorXd sigma = c.report.covariance.diagonal().cwiseSqrt();
    sum2 += error.cwiseQuotient(sigma).cwiseAbs2();
  }
  const Eigen::VectorXd spread = (sum2 / kSeeds).cwiseSqrt();
  for (int i = 0; i < 5; ++i) {
    EXPECT_GT(spread[i], 1 / 1.5) << i;
    EXPECT_LT(spread[i], 1.5) << i;
  }
}

}  // namespace
}  // namespace omnisfm::calib
