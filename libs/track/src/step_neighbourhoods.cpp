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
  // Starts that are not finite lie in no cell, and are nobody's neighbours.
  bool any = false;
  Eigen::Vector2d lowest(0, 0), highest(0, 0);
  for (const Eigen::Vector2d& p : starts_) {
    if (!p.allFinite()) continue;
    lowest = any ? lowest.cwiseMin(p) : p;
    highest = any ? highest.cwiseMax(p) : p;
    any = true;
  }
  if (!any) return;
  origin_ = lowest;
  // Cells as wide as the radius, or wider where the starts lie so far apart that the grid would
  // hold more than kMaxCells cells a side: a neighbourhood still lies within 3 x 3 of them.
  constexpr double kMaxCells = 256;
  const Eigen::Vector2d extent = highest - lowest;
  cell_size_ = std::max({radius_, extent.x() / kMaxCells, extent.y() / kMaxCells});
  if (std::isfinite(cell_size_)) {
    columns_ = std::min(static_cast<int>(kMaxCells), static_cast<int>(extent.x() / cell_size_) + 1);
    rows_ = std::min(static_cast<int>(kMaxCells), static_cast<int>(extent.y() / cell_size_) + 1);
  } else {  // starts beyond double's range apart: one cell
    columns_ = rows_ = 1;
  }
  // Counting sort of the tracks by cell.
  constexpr std::size_t kNoCell = static_cast<std::size_t>(-1);
  std::vector<std::size_t> cells(starts_.size(), kNoCell);
  cell_begin_.assign(static_cast<std::size_t>(columns_) * rows_ + 1, 0);
  for (std::size_t i = 0; i < starts_.size(); ++i) {
    if (!starts_[i].allFinite()) continue;
    cells[i] = static_cast<std::size_t>(row(starts_[i].y())) * columns_ + column(starts_[i].x());
    ++cell_begin_[cells[i] + 1];
  }
  for (std::size_t c = 1; c < cell_begin_.size(); ++c) cell_begin_[c] += cell_begin_[c - 1];
  std::vector<std::size_t> filled(cell_begin_.begin(), cell_begin_.end() - 1);
  by_cell_.resize(cell_begin_.back());
  for (std::size_t i = 0; i < starts_.size(); ++i)
    if (cells[i] != kNoCell) by_cell_[filled[cells[i]]++] = i;
}

int StepNeighbourhoods::clamped_cell(double offset, int cells) const {
  // Written so that a NaN (an infinite offset over an infinite cell) falls in the first cell.
  const double cell = std::floor(offset / cell_size_);
  return cell >= cells - 1 ? cells - 1 : cell > 0 ? static_cast<int>(cell) : 0;
}

int StepNeighbourhoods::column(double x) const { return clamped_cell(x - origin_.x(), columns_); }

int StepNeighbourhoods::row(double y) const { return clamped_cell(y - origin_.y(), rows_); }

StepNeighbourhoods::Neighbours StepNeighbourhoods::neighbours(const Eigen::Vector2d& at,
                                                              std::size_t skip) const {
  Neighbours found;
  if (!at.allFinite() || columns_ == 0) return found;
  // The cells from a little before the radius to a little beyond it, along each axis (at most
  // four: cells are at least as wide as the radius): a start whose rounded distance is within the
  // radius lies at most a few units in the last place beyond it.
  const double reach = radius_ * (1 + 1e-9);
  const int first_row = row(at.y() - reach), last_row = row(at.y() + reach);
  const int first_column = column(at.x() - reach), last_column = column(at.x() + reach);
  std::size_t candidates = 0;
  for (int y = first_row; y <= last_row; ++y) {
    const std::size_t begin = static_cast<std::size_t>(y) * columns_;
    candidates += cell_begin_[begin + last_column + 1] - cell_begin_[begin + first_column];
  }
  // Every candidate's step is written and only those within the radius are kept (the count
  // advances by the test's outcome): this runs for every track every frame, and a branch on
  // where each neighbour lies is mispredicted about as often as taken.
  found.storage.resize(2 * candidates);
  found.xs = found.storage.data();
  found.ys = found.xs + candidates;
  std::size_t n = 0;
  const double radius_squared = radius_ * radius_;
  for (int y = first_row; y <= last_row; ++y) {
    const std::size_t begin = static_cast<std::size_t>(y) * columns_;
    for (std::size_t k = cell_begin_[begin + first_column];
         k < cell_begin_[begin + last_column + 1]; ++k) {
      const std::size_t i = by_cell_[k];
      found.xs[n] = steps_[i].x();
      found.ys[n] = steps_[i].y();
      n += static_cast<std::size_t>(i != skip) &
           static_cast<std::size_t>((starts_[i] - at).squaredNorm() <= radius_squared);
    }
  }
  found.count = n;
  return found;
}

bool StepNeighbourhoods::median_step(const Eigen::Vector2d& at, std::size_t skip,
                                     std::size_t min_tracks, Eigen::Vector2d* step) const {
  Neighbours found = neighbours(at, skip);
  const std::size_t n = found.count;
  if (n == 0 || n < min_tracks) return false;
  *step = Eigen::Vector2d(core::percentile_in_place(found.xs, found.xs + n, 0.5),
                          core::percentile_in_place(found.ys, found.ys + n, 0.5));
  return true;
}

namespace {

// Whether the median of values[0, n) (core::percentile's entry floor(n / 2) of the sorted values)
// lies within [low, high]: it is below low when at least floor(n / 2) + 1 values are, and above
// high when at least n - floor(n / 2) are.
bool median_within(const double* values, std::size_t n, double low, double high) {
  std::size_t below = 0, above = 0;
  for (std::size_t i = 0; i < n; ++i) {
    below += static_cast<std::size_t>(values[i] < low);
    above += static_cast<std::size_t>(values[i] > high);
  }
  const std::size_t k = n / 2;
  return below < k + 1 && above < n - k;
}

}  // namespace

bool StepNeighbourhoods::departs(const Eigen::Vector2d& at, std::size_t skip,
                                 std::size_t min_tracks, const Eigen::Vector2d& step,
                                 double max_deviation) const {
  Neighbours found = neighbours(at, skip);
  const std::size_t n = found.count;
  if (n == 0 || n < min_tracks) return false;
  // Medians within a square of half-width max_deviation / sqrt 2 about the step lie within the
  // circle of radius max_deviation (a little less, so that rounding cannot decide).
  const double half_width = max_deviation / std::sqrt(2.0) * (1 - 1e-9);
  if (median_within(found.xs, n, step.x() - half_width, step.x() + half_width) &&
      median_within(found.ys, n, step.y() - half_width, step.y() + half_width))
    return false;
  const Eigen::Vector2d median(core::percentile_in_place(found.xs, found.xs + n, 0.5),
                               core::percentile_in_place(found.ys, found.ys + n, 0.5));
  return (step - median).norm() > max_deviation;
}

}  // namespace omnisfm::track
