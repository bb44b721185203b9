#include "step_neighbourhoods.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "omnisfm/core/percentile.h"

namespace omnisfm::track {

StepNeighbourhoods::StepNeighbourhoods(std::vector<Eigen::Vector2d> starts,
                                       std::vector<Eigen::Vector2d> steps, double radius)
    : starts_(std::move(starts)), steps_(std::move(steps)), radius_(radius) {
  if (starts_.size() != steps_.size() || !(radius > 0))
    throw std::invalid_argument("StepNeighbourhoods: a step per start and a positive radius");
  if (starts_.empty()) return;
  Eigen::Vector2d lowest = starts_.front(), highest = starts_.front();
  for (const Eigen::Vector2d& p : starts_) {
    lowest = lowest.cwiseMin(p);
    highest = highest.cwiseMax(p);
  }
  origin_ = lowest;
  columns_ = static_cast<int>((highest.x() - lowest.x()) / radius_) + 1;
  rows_ = static_cast<int>((highest.y() - lowest.y()) / radius_) + 1;
  // Counting sort of the tracks by cell.
  std::vector<std::size_t> cells(starts_.size());
  cell_begin_.assign(static_cast<std::size_t>(columns_) * rows_ + 1, 0);
  for (std::size_t i = 0; i < starts_.size(); ++i) {
    cells[i] = static_cast<std::size_t>(row(starts_[i].y())) * columns_ + column(starts_[i].x());
    ++cell_begin_[cells[i] + 1];
  }
  for (std::size_t c = 1; c < cell_begin_.size(); ++c) cell_begin_[c] += cell_begin_[c - 1];
  std::vector<std::size_t> filled(cell_begin_.begin(), cell_begin_.end() - 1);
  by_cell_.resize(starts_.size());
  for (std::size_t i = 0; i < starts_.size(); ++i) by_cell_[filled[cells[i]]++] = i;
}

int StepNeighbourhoods::column(double x) const {
  return static_cast<int>(std::clamp(std::floor((x - origin_.x()) / radius_), 0.0,
                                     static_cast<double>(columns_ - 1)));
}

int StepNeighbourhoods::row(double y) const {
  return static_cast<int>(std::clamp(std::floor((y - origin_.y()) / radius_), 0.0,
                                     static_cast<double>(rows_ - 1)));
}

bool StepNeighbourhoods::median_step(const Eigen::Vector2d& at, std::size_t skip,
                                     std::size_t min_tracks, Eigen::Vector2d* step) const {
  if (!at.allFinite()) return false;
  const double radius_squared = radius_ * radius_;
  std::vector<double> xs, ys;
  const int c = starts_.empty() ? 0 : column(at.x()), r = starts_.empty() ? 0 : row(at.y());
  for (int y = std::max(0, r - 1); y <= std::min(rows_ - 1, r + 1); ++y)
    for (int x = std::max(0, c - 1); x <= std::min(columns_ - 1, c + 1); ++x) {
      const std::size_t cell = static_cast<std::size_t>(y) * columns_ + x;
      for (std::size_t k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
        const std::size_t i = by_cell_[k];
        if (i == skip || (starts_[i] - at).squaredNorm() > radius_squared) continue;
        xs.push_back(steps_[i].x());
        ys.push_back(steps_[i].y());
      }
    }
  if (xs.size() < min_tracks) return false;
  *step = Eigen::Vector2d(core::percentile(xs, 0.5), core::percentile(ys, 0.5));
  return true;
}

}  // namespace omnisfm::track
