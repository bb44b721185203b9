#include "omnisfm/mrpt_plugin/pose_graph_file.h"

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussianInf.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <stdexcept>

#include "eigen_poses.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/io/atomic_write.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Vector6 = Eigen::Matrix<double, 6, 1>;
using Vector12 = Eigen::Matrix<double, 12, 1>;
// The relative scale uncertainty given to a scale the images do not fix at all: lengths then
// carry no information, while the information matrix stays finite.
constexpr double kUnknownScaleSigma = 10;

// The relative pose of frame g's body in frame f's from both frames' batch parameters
// (BatchResult::cam_from_world_parameters).
Eigen::Isometry3d relative_pose(const Vector12& fg, const Eigen::Isometry3d& body_from_cam) {
  return body_from_cam * core::isometry_of(fg.data()) * core::isometry_of(fg.data() + 6).inverse() *
         body_from_cam.inverse();
}

}  // namespace

std::vector<PoseGraphEdge> consecutive_edges(const sfm::BatchResult& batch,
                                             const Eigen::Isometry3d& body_from_cam) {
  const size_t frames = batch.world_from_cam.size();
  if (frames > 0 && (batch.cam_from_world_covariances.size() != frames ||
                     batch.cam_from_world_parameters.size() != frames ||
                     batch.consecutive_cam_from_world_covariances.size() != frames - 1))
    throw std::invalid_argument("consecutive_edges: the batch has no pose covariances");
  std::vector<PoseGraphEdge> edges;
  for (size_t f = 0; f + 1 < frames; ++f) {
    Vector12 fg;
    fg << batch.cam_from_world_parameters[f], batch.cam_from_world_parameters[f + 1];
    Eigen::Matrix<double, 12, 12> joint;
    joint << batch.cam_from_world_covariances[f], batch.consecutive_cam_from_world_covariances[f],
        batch.consecutive_cam_from_world_covariances[f].transpose(),
        batch.cam_from_world_covariances[f + 1];
    const auto relative_of = [&](const Vector12& x) {
      return pose_of(relative_pose(x, body_from_cam));
    };
    const Eigen::Matrix<double, 6, 12> J = mrpt_parameters_jacobian<12>(relative_of, fg);
    PoseGraphEdge edge;
    edge.from = static_cast<int>(f);
    edge.to = static_cast<int>(f + 1);
    edge.relative = relative_pose(fg, body_from_cam);
    edge.covariance = J * joint * J.transpose();
    // A scale held at the filter's is the batch's assumption, not its knowledge: the batch's
    // covariance is conditional on it. Each edge then carries the scale's uncertainty as the
    // images alone give it, along its own translation (edges cannot share it as they should).
    if (batch.scale_source == sfm::BatchScale::kHeldAtStart) {
      const double sigma = std::min(std::isfinite(batch.scale_sigma_relative)
                                        ? batch.scale_sigma_relative
                                        : kUnknownScaleSigma,
                                    kUnknownScaleSigma);
      Vector6 along_scale = Vector6::Zero();
      along_scale.head<3>() = edge.relative.translation();
      edge.covariance += sigma * sigma * along_scale * along_scale.transpose();
    }
    edge.covariance = 0.5 * (edge.covariance + edge.covariance.transpose());
    edges.push_back(edge);
  }
  return edges;
}

void write_pose_graph(const std::string& path, const sfm::BatchResult& batch) {
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  for (size_t f = 0; f < batch.world_from_cam.size(); ++f)
    graph.nodes[f] = pose_of(batch.world_from_cam[f]);
  for (const PoseGraphEdge& edge : consecutive_edges(batch)) {
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(edge.covariance);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        ldlt.vectorD().minCoeff() <= 0)
      throw std::runtime_error(path + ": the relative pose from frame " +
                               std::to_string(edge.from) + " to " + std::to_string(edge.to) +
                               " has a covariance that cannot be inverted");
    const Eigen::Matrix<double, 6, 6> information =
        ldlt.solve(Eigen::Matrix<double, 6, 6>::Identity());
    mrpt::math::CMatrixDouble66 cov_inv;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c) cov_inv(r, c) = 0.5 * (information(r, c) + information(c, r));
    graph.insertEdge(static_cast<mrpt::graphs::TNodeID>(edge.from),
                     static_cast<mrpt::graphs::TNodeID>(edge.to),
                     mrpt::poses::CPose3DPDFGaussianInf(pose_of(edge.relative), cov_inv));
  }
  const bool binary = path.size() >= 9 && path.compare(path.size() - 9, 9, ".graphbin") == 0;
  if (binary) {
    io::write_atomically(path, [&](const std::string& temporary) {
      mrpt::io::CFileGZOutputStream file;
      if (!file.open(temporary, 1))
        throw std::runtime_error(path + ": cannot be written");
      auto archive = mrpt::serialization::archiveFrom(file);
      archive << graph;
    });
  } else {
    io::write_text_atomically(path, [&](std::ostream& out) {
      out.precision(17);
      graph.writeAsText(out);
    });
  }
}

}  // namespace omnisfm::mrpt_plugin
