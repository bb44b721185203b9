// The marginal variance of one scalar, the points eliminated by their 3x3 blocks first, against
// Ceres' covariance of the same problem (a sparse QR of the whole Jacobian).

#include "../src/marginal_variance.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace omnisfm::sfm {
namespace {

// r = A [camera; point; scalar] - b with a fixed random A: 2 residuals on a 6-vector camera, a
// point and a scalar, as a reprojection is.
class LinearCost : public ceres::SizedCostFunction<2, 6, 3, 1> {
 public:
  explicit LinearCost(std::mt19937_64* rng) {
    std::normal_distribution<double> normal;
    for (int i = 0; i < A_.size(); ++i) A_.data()[i] = normal(*rng);
    b_ = Eigen::Vector2d(normal(*rng), normal(*rng));
  }
  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    Eigen::Matrix<double, 10, 1> all;
    all << Eigen::Map<const Eigen::Matrix<double, 6, 1>>(x[0]),
        Eigen::Map<const Eigen::Vector3d>(x[1]), x[2][0];
    Eigen::Map<Eigen::Vector2d> r(residuals);
    r = A_ * all - b_;
    if (!jacobians) return true;
    const int offsets[3] = {0, 6, 9}, sizes[3] = {6, 3, 1};
    for (int k = 0; k < 3; ++k)
      if (jacobians[k])
        for (int row = 0; row < 2; ++row)
          for (int c = 0; c < sizes[k]; ++c) jacobians[k][row * sizes[k] + c] = A_(row, offsets[k] + c);
    return true;
  }

 private:
  Eigen::Matrix<double, 2, 10> A_;
  Eigen::Vector2d b_;
};

// 5 cameras: the reduced system is factored dense; 250 (1,500 parameters): sparse.
TEST(MarginalVariance, EqualsCeresCovarianceOfTheWholeProblem) {
  for (const auto& [camera_count, subset_manifold] :
       std::vector<std::pair<int, bool>>{{5, false}, {5, true}, {250, true}}) {
    std::mt19937_64 rng(7);
    std::vector<Eigen::Matrix<double, 6, 1>> cameras(camera_count,
                                                     Eigen::Matrix<double, 6, 1>::Zero());
    std::vector<Eigen::Vector3d> points(8, Eigen::Vector3d::Zero());
    double scalar = 1;
    ceres::Problem problem;
    for (auto& camera : cameras)
      for (auto& point : points)
        problem.AddResidualBlock(new LinearCost(&rng), nullptr, camera.data(), point.data(),
                                 &scalar);
    problem.SetParameterBlockConstant(cameras[0].data());
    if (subset_manifold)
      problem.SetManifold(cameras[1].data(), new ceres::SubsetManifold(6, {4}));
    std::vector<double*> point_blocks;
    for (auto& point : points) point_blocks.push_back(point.data());
    const double variance = marginal_variance(&problem, &scalar, point_blocks);

    ceres::Covariance::Options options;
    options.algorithm_type = ceres::SPARSE_QR;
    ceres::Covariance covariance(options);
    const std::vector<std::pair<const double*, const double*>> block{{&scalar, &scalar}};
    ASSERT_TRUE(covariance.Compute(block, &problem));
    double expected = 0;
    covariance.GetCovarianceBlock(&scalar, &scalar, &expected);
    EXPECT_GT(expected, 0);
    EXPECT_NEAR(variance, expected, 1e-9 * expected) << camera_count << " cameras";
  }
}

// Nothing fixes a scalar that no residual sees beyond what a free block can absorb.
TEST(MarginalVariance, IsInfiniteWhenNothingFixesTheScalar) {
  std::mt19937_64 rng(8);
  Eigen::Matrix<double, 6, 1> camera = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  double scalar = 1;
  ceres::Problem problem;
  // Two residuals on ten parameters: singular.
  problem.AddResidualBlock(new LinearCost(&rng), nullptr, camera.data(), point.data(), &scalar);
  EXPECT_EQ(marginal_variance(&problem, &scalar, {point.data()}), INFINITY);
  double other = 0;
  problem.AddParameterBlock(&other, 1);
  problem.SetParameterBlockConstant(&other);
  EXPECT_TRUE(std::isnan(marginal_variance(&problem, &other, {point.data()})));
}

}  // namespace
}  // namespace omnisfm::sfm
