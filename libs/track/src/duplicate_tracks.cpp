#include "duplicate_tracks.h"

#include <algorithm>
#include <stdexcept>

namespace omnisfm::track {

std::vector<bool> younger_duplicates(const std::vector<Eigen::Vector2d>& positions,
                                     const std::vector<std::pair<int, int>>& started,
                                     double separation) {
  if (positions.size() != started.size())
    throw std::invalid_argument("younger_duplicates: a start per position");
  std::vector<size_t> by_x;
  for (size_t i = 0; i < positions.size(); ++i)
    if (positions[i].allFinite()) by_x.push_back(i);
  std::sort(by_x.begin(), by_x.end(),
            [&](size_t a, size_t b) { return positions[a].x() < positions[b].x(); });
  std::vector<std::pair<size_t, size_t>> close;
  for (size_t a = 0; a < by_x.size(); ++a)
    for (size_t b = a + 1;
         b < by_x.size() && positions[by_x[b]].x() - positions[by_x[a]].x() < separation; ++b)
      if ((positions[by_x[a]] - positions[by_x[b]]).norm() < separation)
        close.emplace_back(std::min(by_x[a], by_x[b]), std::max(by_x[a], by_x[b]));
  std::sort(close.begin(), close.end());
  std::vector<bool> ended(positions.size(), false);
  for (const auto& [i, j] : close) {
    if (ended[i] || ended[j]) continue;
    ended[started[i] > started[j] ? i : j] = true;
  }
  return ended;
}

}  // namespace omnisfm::track
