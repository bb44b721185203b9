// The pose graph's edges against the truth: the relative poses' errors over seeds of the rover,
// the lab and the crane,
// normalised by the covariances batch.graph publishes. Fifteen batches: not for the sanitizers'
// build.

#include <gtest/gtest.h>
#include <mrpt/math/wrap2pi.h>

#include <string>

#include "eigen_poses.h"
#include "nees_tally.h"
#include "omnisfm/mrpt_plugin/pose_graph_file.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;

Vector6 mrpt_parameters(const Eigen::Isometry3d& T) { return mrpt_parameters_of(pose_of(T)); }

// The edges' normalised errors squared against the true relative poses (six degrees of freedom
// each) over the seeds of a scenario.
NeesTally edges_against_truth(const std::string& scenario, std::uint64_t first,
                              std::uint64_t last) {
  NeesTally c(12.592);  // chi-square, 6 degrees of freedom, 95 %
  for (std::uint64_t seed = first; seed <= last; ++seed) {
    sim::SimulationOptions options;
    options.scenario = scenario;
    options.seed = seed;
    const sim::Dataset d = sim::simulate(options);
    const sfm::SfmResult r = sfm::run_sfm(d.camera, d.observations, sfm::SfmSettings{});
    EXPECT_TRUE(r.batch.converged) << scenario << " " << seed;
    for (const PoseGraphEdge& edge : consecutive_edges(r.batch)) {
      const Eigen::Isometry3d truth =
          d.world_from_cam[edge.from].inverse() * d.world_from_cam[edge.to];
      Vector6 e = mrpt_parameters(edge.relative) - mrpt_parameters(truth);
      for (int i = 3; i < 6; ++i) e[i] = mrpt::math::wrapToPi(e[i]);
      c.add(e.dot(edge.covariance.ldlt().solve(e)));
    }
  }
  return c;
}

// Consistent: 6 and 95 %. Measured (edges_against_truth): rover 1-5 6.76 / 94.4 % and 6-15 5.55
// / 96.3 % (the scale from the images); lab 1-5 4.38 / 97.5 % and crane 1-5 9.27 / 78.4 % (the
// scale held, its uncertainty on the edges: without it 528 and 179, 0 % inside).
TEST(PoseGraphFile, EdgesAreAsCertainAsTheirErrorsOverRoverSeeds) {
  const NeesTally c = edges_against_truth("rover", 1, 5);
  EXPECT_GT(c.mean(), 4.5);
  EXPECT_LT(c.mean(), 8.0);
  EXPECT_GT(c.inside(), 0.90);
}

TEST(PoseGraphFile, AHeldScaleIsUncertainOnTheEdges) {
  const NeesTally lab = edges_against_truth("lab", 1, 5);
  EXPECT_LT(lab.mean(), 8.0);
  EXPECT_GT(lab.inside(), 0.90);
  // The crane's edges stay somewhat overconfident: what is left is not the scale.
  const NeesTally crane = edges_against_truth("crane", 1, 5);
  EXPECT_LT(crane.mean(), 12.0);
  EXPECT_GT(crane.inside(), 0.70);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
