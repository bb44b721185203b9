#pragma once
// Horn's closed-form absolute orientation: the similarity (or rigid motion) b ~ s R a + t that
// best maps one point set onto another in least squares.

#include <Eigen/Core>
#include <vector>

namespace omnisfm::eval {

struct Similarity {
  double scale = 1;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d apply(const Eigen::Vector3d& a) const { return scale * rotation * a + translation; }
};

// Minimises sum |s R a_i + t - b_i|^2 (s = 1 when with_scale is false). Needs 3 or more
// non-collinear pairs; throws std::invalid_argument otherwise.
Similarity align(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                 bool with_scale = true);

}  // namespace omnisfm::eval
