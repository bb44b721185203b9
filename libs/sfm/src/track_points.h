#pragma once
// The batch's points as Ceres' parameter blocks: one array in track order, its size fixed once
// made. Ceres eliminates the points in the order of their addresses, and sums their shares of the
// reduced system in that order: held in a std::map, each point where the heap put it, the same
// input gave answers 1e-7 m apart from one run to the next (an output folder's name was enough).

#include <Eigen/Core>
#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace omnisfm::sfm {

class TrackPoints {
 public:
  using Entry = std::pair<int, Eigen::Vector3d>;  // track, point

  TrackPoints() = default;
  explicit TrackPoints(const std::map<int, Eigen::Vector3d>& points)
      : entries_(points.begin(), points.end()) {}

  std::vector<Entry>::iterator begin() { return entries_.begin(); }
  std::vector<Entry>::iterator end() { return entries_.end(); }
  std::vector<Entry>::const_iterator begin() const { return entries_.begin(); }
  std::vector<Entry>::const_iterator end() const { return entries_.end(); }

  // The track's point, or nullptr when it has none.
  Eigen::Vector3d* find(int track) { return const_cast<Eigen::Vector3d*>(find_const(track)); }
  const Eigen::Vector3d* find(int track) const { return find_const(track); }

  Eigen::Vector3d& at(int track) { return *checked(find(track), track); }
  const Eigen::Vector3d& at(int track) const { return *checked(find(track), track); }

 private:
  const Eigen::Vector3d* find_const(int track) const {
    const auto at = std::lower_bound(entries_.begin(), entries_.end(), track,
                                     [](const Entry& e, int t) { return e.first < t; });
    return at != entries_.end() && at->first == track ? &at->second : nullptr;
  }
  template <typename Point>
  static Point* checked(Point* point, int track) {
    if (!point) throw std::out_of_range("no point for track " + std::to_string(track));
    return point;
  }

  std::vector<Entry> entries_;
};

}  // namespace omnisfm::sfm
