#pragma once
// The paper's error figures for an estimated trajectory against ground truth, after aligning the
// estimate's camera positions onto the truth (Horn, with scale unless the scale is known).

#include <Eigen/Geometry>
#include <map>
#include <set>
#include <vector>

#include "omnisfm/eval/similarity_alignment.h"

namespace omnisfm::eval {

struct TrajectoryErrors {
  Similarity alignment;                 // estimate -> ground truth
  double distance_travelled_m = 0;      // along the ground truth
  double mean_translation_error_m = 0;  // camera positions after alignment
  double rms_translation_error_m = 0;
  double translation_error_percent = 0;  // mean error / distance travelled
  double mean_rotation_error_deg = 0;   // orientation after alignment
  double mean_yaw_error_deg = 0;        // about the world's z axis
  double rotation_spread_deg = 0;       // estimates around their mean (a rig that does not rotate)
  std::vector<double> translation_errors_m;  // per frame
};

// world_from_cam poses, one per frame in both. Throws std::invalid_argument for sizes that differ
// or fewer than 3 frames.
TrajectoryErrors trajectory_errors(const std::vector<Eigen::Isometry3d>& estimate,
                                   const std::vector<Eigen::Isometry3d>& truth, bool with_scale);

struct PointErrors {
  int num_points = 0;
  int centre_frame = 0;             // the camera nearest the middle of the true trajectory
  double mean_depth_error_m = 0;    // |depth_estimate - depth_truth| from that camera
  double mean_depth_error_percent = 0;
};

// Depth errors of the estimated points (aligned with `alignment`) seen from the centremost
// camera, over the tracks present in both maps.
PointErrors point_errors(const std::map<int, Eigen::Vector3d>& estimate,
                         const std::map<int, Eigen::Vector3d>& truth,
                         const std::vector<Eigen::Isometry3d>& estimate_poses,
                         const std::vector<Eigen::Isometry3d>& truth_poses,
                         const Similarity& alignment);

struct OutlierDetection {
  int detected = 0, actual = 0, correct = 0;
  double precision = 1, recall = 1;  // 1 when there is nothing to detect or nothing detected
};

OutlierDetection outlier_detection(const std::set<int>& detected_tracks,
                                   const std::set<int>& true_outlier_tracks);

// The angle, degrees, between the estimated and the true direction of travel from frame f to
// f + span, each in its own camera's frame at f (world_from_cam poses): what a drift of the
// camera's place in the world shows while its turning and its map stay right.
double travel_direction_error_deg(const std::vector<Eigen::Isometry3d>& estimate,
                                  const std::vector<Eigen::Isometry3d>& truth, int f, int span);

}  // namespace omnisfm::eval
