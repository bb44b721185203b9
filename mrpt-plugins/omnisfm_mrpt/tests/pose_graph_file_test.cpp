// batch.graph: the batch's poses and consecutive relative poses as MRPT's pose graph. Read back by
// MRPT's own loader; the edges' covariances checked against sampled relative poses (and, in
// pose_graph_consistency_test.cpp, against the true relative poses' errors over rover seeds).

#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/math/wrap2pi.h>

#include <unistd.h>

#include <filesystem>
#include <iostream>
#include <random>

#include "eigen_poses.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/mrpt_plugin/pose_graph_file.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/scenario.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

Vector6 mrpt_parameters(const Eigen::Isometry3d& T) { return mrpt_parameters_of(pose_of(T)); }

Vector6 difference(const Vector6& a, const Vector6& b) {
  Vector6 d = a - b;
  for (int i = 3; i < 6; ++i) d[i] = mrpt::math::wrapToPi(d[i]);
  return d;
}

sim::Dataset rover(std::uint64_t seed) {
  sim::SimulationOptions options;
  options.scenario = "rover";
  options.seed = seed;
  return sim::simulate(options);
}

sfm::SfmResult batch_of(const sim::Dataset& d) {
  return sfm::run_sfm(d.camera, d.observations, sfm::SfmSettings{});
}

std::string temporary_graph(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("omnisfm_") + name + "_" + std::to_string(::getpid()) + ".graph"))
      .string();
}

mrpt::graphs::CNetworkOfPoses3DInf written_and_read(const sfm::BatchResult& batch,
                                                   const char* extension) {
  const std::string path = temporary_graph("loader") + extension;
  write_pose_graph(path, batch);
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  if (std::string(extension) == ".graphbin") {
    mrpt::io::CFileGZInputStream file(path);
    auto archive = mrpt::serialization::archiveFrom(file);
    archive >> graph;
  } else {
    graph.loadFromTextFile(path);
  }
  std::filesystem::remove(path);
  return graph;
}

TEST(PoseGraphFile, MrptReadsTheBatchsPosesAndEdges) {
  const sim::Dataset d = rover(1);
  const sfm::SfmResult r = batch_of(d);
  ASSERT_TRUE(r.batch.converged);
  const size_t frames = r.batch.world_from_cam.size();
  const std::vector<PoseGraphEdge> edges = consecutive_edges(r.batch);
  ASSERT_EQ(edges.size(), frames - 1);
  for (const char* extension : {".graph", ".graphbin"}) {
    SCOPED_TRACE(extension);
    const mrpt::graphs::CNetworkOfPoses3DInf graph = written_and_read(r.batch, extension);
    ASSERT_EQ(graph.nodes.size(), frames);
    for (size_t f = 0; f < frames; ++f) {
      const Eigen::Isometry3d read = isometry_of(graph.nodes.at(f));
      const Eigen::Isometry3d& written = r.batch.world_from_cam[f];
      EXPECT_LT((read.matrix() - written.matrix()).cwiseAbs().maxCoeff(), 1e-12) << f;
    }
    ASSERT_EQ(graph.edges.size(), frames - 1);
    for (const PoseGraphEdge& edge : edges) {
      const auto it = graph.edges.find({edge.from, edge.to});
      ASSERT_NE(it, graph.edges.end()) << edge.from;
      const Eigen::Isometry3d read = isometry_of(it->second.mean);
      EXPECT_LT((read.matrix() - edge.relative.matrix()).cwiseAbs().maxCoeff(), 1e-12);
      // The edge is the relative pose of its vertices: the batch is already the graph's optimum.
      const Eigen::Isometry3d of_vertices =
          isometry_of(graph.nodes.at(edge.from)).inverse() * isometry_of(graph.nodes.at(edge.to));
      EXPECT_LT((of_vertices.matrix() - read.matrix()).cwiseAbs().maxCoeff(), 1e-9);
      // The information inverts the covariance, up to the digits written; MRPT 2.5's text
      // loader loses the three entries between yaw, pitch and roll (pose_graph_file.h).
      const Matrix6 information = it->second.cov_inv.asEigen();
      const Matrix6 expected = edge.covariance.inverse();
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          if (std::string(extension) == ".graph" && i >= 3 && j >= 3 && i != j) continue;
          EXPECT_NEAR(information(i, j), expected(i, j),
                      1e-8 * std::sqrt(expected(i, i) * expected(j, j)))
              << edge.from << ": " << i << "," << j;
        }
    }
  }
}

// The propagation into MRPT's parameters, against relative poses drawn from the joint Gaussian
// of two poses (small enough for the linearisation to hold).
TEST(PoseGraphFile, EdgeCovarianceIsThatOfSampledRelativePoses) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  sfm::BatchResult batch;
  const Vector6 a = (Vector6() << 0.3, -2.9, 0.4, 1.0, -0.5, 2.0).finished();  // angle near pi
  const Vector6 b = (Vector6() << 0.35, -2.85, 0.42, 1.1, -0.45, 2.05).finished();
  batch.cam_from_world_parameters = {a, b};
  batch.world_from_cam = {core::isometry_of(a).inverse(), core::isometry_of(b).inverse()};
  Eigen::Matrix<double, 12, 12> L = Eigen::Matrix<double, 12, 12>::Zero();
  for (int r = 0; r < 12; ++r)
    for (int c = 0; c <= r; ++c) L(r, c) = (r == c ? 1.0 : 0.3 * normal(rng)) * 1e-3;
  const Eigen::Matrix<double, 12, 12> joint = L * L.transpose();
  batch.cam_from_world_covariances = {joint.topLeftCorner<6, 6>(),
                                      joint.bottomRightCorner<6, 6>()};
  batch.consecutive_cam_from_world_covariances = {joint.topRightCorner<6, 6>()};
  const std::vector<PoseGraphEdge> edges = consecutive_edges(batch);
  ASSERT_EQ(edges.size(), 1u);
  const Vector6 mean = mrpt_parameters(edges[0].relative);

  constexpr int kDraws = 40000;
  Matrix6 sampled = Matrix6::Zero();
  for (int i = 0; i < kDraws; ++i) {
    Eigen::Matrix<double, 12, 1> z;
    for (int k = 0; k < 12; ++k) z[k] = normal(rng);
    const Eigen::Matrix<double, 12, 1> x =
        (Eigen::Matrix<double, 12, 1>() << a, b).finished() + L * z;
    const Eigen::Isometry3d relative =
        core::isometry_of(x.data()) * core::isometry_of(x.data() + 6).inverse();
    const Vector6 e = difference(mrpt_parameters(relative), mean);
    sampled += e * e.transpose() / kDraws;
  }
  // Each entry within 4 % of the diagonal's scale (40,000 draws: about 1 % sampling error).
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      EXPECT_NEAR(edges[0].covariance(r, c), sampled(r, c),
                  0.04 * std::sqrt(sampled(r, r) * sampled(c, c)))
          << r << "," << c;
}

TEST(PoseGraphFile, NoCovariancesNoGraph) {
  sfm::BatchResult batch;
  batch.world_from_cam.resize(3, Eigen::Isometry3d::Identity());
  batch.cam_from_world_parameters.resize(3, Vector6::Zero());
  EXPECT_THROW(consecutive_edges(batch), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
