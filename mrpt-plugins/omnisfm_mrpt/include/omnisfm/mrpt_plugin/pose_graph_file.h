#pragma once
// The batch's camera poses as an MRPT pose graph (mrpt::graphs::CNetworkOfPoses3DInf) in its text
// format, which stock `graph-slam --3d` reads: a VERTEX3 per frame, the camera's pose in the
// batch's world (world_from_cam), and an EDGE3 from each frame to the next, their relative pose
// with its information matrix. That matrix inverts the relative pose's covariance, propagated
// from the batch's joint covariance of the two poses (BatchResult::cam_from_world_covariances
// and consecutive_cam_from_world_covariances, over cam_from_world_parameters) into MRPT's
// parameters (x y z yaw pitch roll), so the edges are as certain as the batch is, correlations
// included. Frame 0 holds the gauge: its covariance is zero. Where the batch held the scale at the
// filter's (its covariance then conditional on that scale), each edge's translation also carries
// the scale's uncertainty as the images give it (BatchResult::scale_sigma_relative, at most 10).
// MRPT-free: the omnisfm command links it without seeing MRPT.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "omnisfm/sfm/batch_adjustment.h"

namespace omnisfm::mrpt_plugin {

struct PoseGraphEdge {
  int from = 0, to = 0;
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();  // the pose of `to` in `from`
  // Over MRPT's pose parameters x y z yaw pitch roll, in that order.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
};

// The edges between consecutive frames: the cameras' relative poses, or with `body_from_cam` those
// of the frame it places on each camera (a robot's body carrying it). Throws
// std::invalid_argument when the batch has no covariances for its poses.
std::vector<PoseGraphEdge> consecutive_edges(
    const sfm::BatchResult& batch,
    const Eigen::Isometry3d& body_from_cam = Eigen::Isometry3d::Identity());

// Writes `path` whole or not at all: MRPT's text format (at full precision), or with a name ending
// in ".graphbin" MRPT's gzip-compressed serialisation of the graph. The text keeps every number,
// but MRPT 2.5's text loader drops the information between yaw, pitch and roll (it reads them
// into one triangle of the matrix and then overwrites it from the other), so programs that need
// the whole matrix read the .graphbin (graph-slam 2.5 reads only text). Throws what
// consecutive_edges throws,
// and std::runtime_error naming `path` when it cannot be written, or when an edge's covariance
// cannot be inverted.
void write_pose_graph(const std::string& path, const sfm::BatchResult& batch);

}  // namespace omnisfm::mrpt_plugin
