#include "omnisfm/eval/similarity_alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "omnisfm/eval/trajectory_errors.h"

namespace omnisfm::eval {
namespace {

TEST(SimilarityAlignment, RecoversAKnownSimilarityExactly) {
  std::mt19937 rng(3);
  std::normal_distribution<double> g(0, 2);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.3, -4, 2);
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 20; ++i) {
    a.emplace_back(g(rng), g(rng), g(rng));
    b.push_back(2.5 * R * a.back() + t);
  }
  const Similarity s = align(a, b);
  EXPECT_NEAR(s.scale, 2.5, 1e-12);
  EXPECT_LT((s.rotation - R).norm(), 1e-12);
  EXPECT_LT((s.translation - t).norm(), 1e-11);
  const Similarity rigid = align(a, b, false);
  EXPECT_EQ(rigid.scale, 1.0);
  EXPECT_LT((rigid.rotation - R).norm(), 1e-12);
}

TEST(SimilarityAlignment, MinimisesTheSquaredError) {
  // With noise, no small change of the result lowers the cost.
  std::mt19937 rng(4);
  std::normal_distribution<double> g(0, 1), noise(0, 0.05);
  std::vector<Eigen::Vector3d> a, b;
  for (int i = 0; i < 30; ++i) {
    a.emplace_back(g(rng), g(rng), g(rng));
    b.push_back(0.7 * a.back() + Eigen::Vector3d(1, 2, 3) +
                Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
  }
  const Similarity s = align(a, b);
  auto cost = [&](const Similarity& x) {
    double c = 0;
    for (size_t i = 0; i < a.size(); ++i) c += (x.apply(a[i]) - b[i]).squaredNorm();
    return c;
  };
  const double best = cost(s);
  for (int k = 0; k < 7; ++k)
    for (double step : {-1e-4, 1e-4}) {
      Similarity x = s;
      if (k < 3) x.rotation = Eigen::AngleAxisd(step, Eigen::Vector3d::Unit(k)).toRotationMatrix() * x.rotation;
      else if (k < 6) x.translation[k - 3] += step;
      else x.scale += step;
      EXPECT_GE(cost(x), best);
    }
}

TEST(SimilarityAlignment, RejectsDegenerateSets) {
  std::vector<Eigen::Vector3d> line{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_THROW(align(line, line), std::invalid_argument);
  EXPECT_THROW(align({{0, 0, 0}}, {{0, 0, 0}}), std::invalid_argument);
}

TEST(TrajectoryErrors, FiguresOfAKnownError) {
  std::vector<Eigen::Isometry3d> truth, estimate;
  for (int i = 0; i < 10; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << i * 0.1, (i % 3) * 0.05, 0;
    truth.push_back(T);
    // The estimate: the truth scaled by 3, plus a 2 degree yaw on every pose.
    Eigen::Isometry3d E = T;
    E.translation() *= 3;
    E.linear() = Eigen::AngleAxisd(2 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    estimate.push_back(E);
  }
  const TrajectoryErrors e = trajectory_errors(estimate, truth, true);
  EXPECT_NEAR(e.alignment.scale, 1.0 / 3, 1e-12);
  EXPECT_NEAR(e.mean_translation_error_m, 0, 1e-12);
  EXPECT_NEAR(e.mean_rotation_error_deg, 2, 1e-9);
  EXPECT_NEAR(e.mean_yaw_error_deg, 2, 1e-9);
  EXPECT_NEAR(e.rotation_spread_deg, 0, 1e-9);
  EXPECT_THROW(trajectory_errors({truth[0]}, {truth[0]}, true), std::invalid_argument);
  const OutlierDetection o = outlier_detection({1, 2, 3, 9}, {1, 2, 3, 4, 5});
  EXPECT_DOUBLE_EQ(o.precision, 0.75);
  EXPECT_DOUBLE_EQ(o.recall, 0.6);
}

}  // namespace
}  // namespace omnisfm::eval
