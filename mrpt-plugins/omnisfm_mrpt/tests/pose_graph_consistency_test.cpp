// The pose graph's edges against the truth: the relative poses' errors over rover seeds,
// normalised by the covariances batch.graph publishes. Five batches: not for the sanitizers' build.

#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include "eigen_poses.h"
#include "omnisfm/mrpt_plugin/pose_graph_file.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

Vector6 mrpt_parameters(const Eigen::Isometry3d& T) { return mrpt_parameters_of(pose_of(T)); }

// The edges' uncertainty against the true relative poses: normalised errors squared over rover
// seeds (six degrees of freedom each).
TEST(PoseGraphFile, EdgesAreAsCertainAsTheirErrorsOverRoverSeeds) {
  double nees_sum = 0;
  int count = 0, inside = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    sim::SimulationOptions options;
    options.scenario = "rover";
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    const sfm::SfmResult r = sfm::run_sfm(d.camera, d.observations, sfm::SfmSettings{});
    ASSERT_TRUE(r.batch.converged) << seed;
    for (const PoseGraphEdge& edge : consecutive_edges(r.batch)) {
      const Eigen::Isometry3d truth =
          d.world_from_cam[edge.from].inverse() * d.world_from_cam[edge.to];
      Vector6 e = mrpt_parameters(edge.relative) - mrpt_parameters(truth);
      for (int i = 3; i < 6; ++i) e[i] = mrpt::math::wrapToPi(e[i]);
      const double nees = e.dot(edge.covariance.ldlt().solve(e));
      nees_sum += nees;
      inside += nees <= 12.592;  // chi-square, 6 degrees of freedom, 95 %
      ++count;
    }
  }
  const double mean = nees_sum / count;
  // Measured: 6.76, 94.4 % inside (745 edges). Consistent: 6 and 95 %.
  EXPECT_GT(mean, 4.5);
  EXPECT_LT(mean, 8.0);
  EXPECT_GT(static_cast<double>(inside) / count, 0.90);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
