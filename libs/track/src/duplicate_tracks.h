#pragma once
// Live tracks that follow the same feature: of two closer than a separation, the younger ends.

#include <Eigen/Core>
#include <utility>
#include <vector>

namespace omnisfm::track {

// Per track whether it ends. Pairs closer than `separation` are taken in the order of their
// indices (i < j, by i then j), skipping a pair where either has ended already; of a pair the
// younger ends: the greater (first frame, id) in `started`. A position that is not finite is
// near nothing. The pairs are found in a sweep along x, not by reading every pair.
std::vector<bool> younger_duplicates(const std::vector<Eigen::Vector2d>& positions,
                                     const std::vector<std::pair<int, int>>& started,
                                     double separation);

}  // namespace omnisfm::track
