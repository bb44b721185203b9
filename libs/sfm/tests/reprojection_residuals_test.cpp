// Residuals under the true poses and points are the simulated tracking noise; the outlier flag and
// the left-out count follow their definitions.

#include "omnisfm/sfm/reprojection_residuals.h"

#include <gtest/gtest.h>

#include <cmath>

#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {
namespace {

struct Truth {
  std::vector<Eigen::Isometry3d> world_from_cam;
  std::map<int, Eigen::Vector3d> points;
};

Truth truth_of(const sim::Dataset& d) {
  Truth t;
  t.world_from_cam = d.world_from_cam;
  for (size_t k = 0; k < d.track_points.size(); ++k) t.points[static_cast<int>(k)] = d.track_points[k];
  return t;
}

sim::Dataset rover(double noise_px) {
  sim::SimulationOptions options;
  options.scenario = "rover";
  options.tracking_noise_px = noise_px;
  return sim::simulate(options);
}

std::set<int> outlier_tracks(const sim::Dataset& d) {
  std::set<int> tracks;
  for (const auto& o : d.outliers) tracks.insert(o.track);
  return tracks;
}

TEST(ReprojectionResiduals, AreZeroForNoiseFreeInliersUnderTheTruth) {
  const sim::Dataset d = rover(0.0);
  const Truth t = truth_of(d);
  int left_out = -1;
  const auto residuals = reprojection_residuals(d.camera, d.observations, t.world_from_cam,
                                                t.points, outlier_tracks(d), &left_out);
  EXPECT_EQ(left_out, 0);
  ASSERT_EQ(residuals.size(), d.observations.size());
  int inliers = 0, outliers = 0;
  for (const auto& r : residuals) {
    if (r.outlier) {
      ++outliers;
      continue;
    }
    ++inliers;
    EXPECT_LT(r.residual.norm(), 1e-6) << "frame " << r.frame << " track " << r.track;
  }
  EXPECT_GT(inliers, 1000);
  EXPECT_GT(outliers, 0);
}

TEST(ReprojectionResiduals, HaveTheNoiseSpreadUnderTheTruth) {
  const sim::Dataset d = rover(0.5);
  const Truth t = truth_of(d);
  const auto residuals =
      reprojection_residuals(d.camera, d.observations, t.world_from_cam, t.points, outlier_tracks(d));
  double sum_sq = 0;
  int n = 0;
  for (const auto& r : residuals) {
    if (r.outlier) continue;
    sum_sq += r.residual.squaredNorm();
    n += 2;
  }
  // Thousands of coordinates: the sample RMS within 5 % of the 0.5 px noise.
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.5, 0.025);
}

TEST(ReprojectionResiduals, LeaveOutWhatHasNoEstimate) {
  const sim::Dataset d = rover(0.0);
  Truth t = truth_of(d);
  t.points.erase(0);
  t.world_from_cam.pop_back();
  int expected = 0;
  const int last = static_cast<int>(d.world_from_cam.size()) - 1;
  for (const auto& o : d.observations) expected += (o.track == 0 || o.frame == last);
  int left_out = -1;
  const auto residuals =
      reprojection_residuals(d.camera, d.observations, t.world_from_cam, t.points, {}, &left_out);
  EXPECT_EQ(left_out, expected);
  EXPECT_EQ(residuals.size() + expected, d.observations.size());
}

}  // namespace
}  // namespace omnisfm::sfm
