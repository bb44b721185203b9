#include "omnisfm/eval/truth_comparison.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "omnisfm/io/input_error.h"

namespace omnisfm::eval {
namespace {

// A circle of camera poses, and an estimate that is the truth in another frame at half the scale.
struct Fixture {
  std::vector<io::StampedPose> truth;
  sfm::SfmResult result;
};

Fixture circle(int frames) {
  Fixture f;
  Eigen::Isometry3d estimate_from_world = Eigen::Isometry3d::Identity();
  estimate_from_world.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  estimate_from_world.translation() = Eigen::Vector3d(4, -1, 2);
  for (int k = 0; k < frames; ++k) {
    const double a = 0.2 * k;
    Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
    world_from_cam.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    world_from_cam.translation() = Eigen::Vector3d(3 * std::cos(a), 3 * std::sin(a), 0.1 * k);
    f.truth.push_back({static_cast<double>(k), world_from_cam});
    Eigen::Isometry3d in_estimate = estimate_from_world * world_from_cam;
    in_estimate.translation() *= 0.5;
    f.result.online_world_from_cam.push_back(in_estimate);
  }
  f.result.batch.world_from_cam = f.result.online_world_from_cam;
  f.result.num_frames = frames;
  return f;
}

TEST(TruthComparison, ASimilarTrajectoryHasNoErrorAfterTheSimilarity) {
  const Fixture f = circle(30);
  const TruthComparison c = compare_with_truth(f.result, true, f.truth, "gt.tum", true);
  ASSERT_EQ(c.estimates.size(), 2u);
  EXPECT_EQ(c.estimates[0].name, "online");
  EXPECT_EQ(c.estimates[1].name, "batch");
  EXPECT_NEAR(c.estimates[0].alignment.scale, 2.0, 1e-9);
  const TrajectoryErrors e = trajectory_errors(c.estimates[0].world_from_cam, c.truth, true);
  EXPECT_LT(e.mean_translation_error_m, 1e-9);
  EXPECT_LT(e.mean_rotation_error_deg, 1e-6);
  // Four lines: each estimate after the similarity, and rigidly (where half the scale shows).
  EXPECT_NE(c.report.find("online  translation 0.0000 m mean"), std::string::npos) << c.report;
  EXPECT_NE(c.report.find("batch/rigid translation"), std::string::npos) << c.report;
  EXPECT_EQ(std::count(c.report.begin(), c.report.end(), '\n'), 4);
}

TEST(TruthComparison, ATruthShorterThanTheTracksIsRefusedNamingItsFile) {
  Fixture f = circle(10);
  f.truth.pop_back();
  try {
    compare_with_truth(f.result, false, f.truth, "gt.tum");
    FAIL() << "not refused";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.file(), "gt.tum");
    EXPECT_EQ(e.message(), "has 9 poses for 10 frames");
  }
}

// The last images gave no tracks: the truth runs on beyond the estimate, and the figures are
// those of the frames both have, said in the report.
TEST(TruthComparison, ATruthLongerThanTheTracksIsComparedOverTheirFrames) {
  Fixture f = circle(10);
  Fixture longer = circle(13);
  const TruthComparison c = compare_with_truth(f.result, true, longer.truth, "gt.tum");
  ASSERT_EQ(c.truth.size(), 10u);
  // Its first ten, frame by frame.
  EXPECT_TRUE(c.truth[0].isApprox(longer.truth[0].world_from_cam));
  EXPECT_TRUE(c.truth[9].isApprox(longer.truth[9].world_from_cam));
  const TrajectoryErrors e = trajectory_errors(c.estimates[0].world_from_cam, c.truth, true);
  EXPECT_LT(e.mean_translation_error_m, 1e-9);
  EXPECT_EQ(c.report.rfind("truth: gt.tum has 13 poses and the tracks end at frame 9; compared "
                           "over its first 10\n",
                           0),
            0u)
      << c.report;
}

}  // namespace
}  // namespace omnisfm::eval
