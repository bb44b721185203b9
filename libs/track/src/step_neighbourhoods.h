#pragma once
// The tracks' steps in one frame, looked up by where each step began: the median step of the
// tracks near a place reads the few cells (at least as wide as the neighbourhood's radius) about
// it instead of every track. The jump check asks for every track's neighbourhood, which, read
// track by track, cost as the tracks' count squared.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace omnisfm::track {

class StepNeighbourhoods {
 public:
  // starts[i]: where track i's step began; steps[i]: the step. radius > 0.
  StepNeighbourhoods(std::vector<Eigen::Vector2d> starts, std::vector<Eigen::Vector2d> steps,
                     double radius);

  // The median (core::percentile's: the upper middle one of an even count) of the steps, per
  // coordinate, of the tracks whose step began within the radius of `at`, track `skip` left out
  // (pass the count for none); false with fewer than min_tracks of them, or none.
  bool median_step(const Eigen::Vector2d& at, std::size_t skip, std::size_t min_tracks,
                   Eigen::Vector2d* step) const;
  // Whether median_step(at, skip, min_tracks) finds a median that `step` is farther than
  // max_deviation from. The medians are taken only where counting the steps on either side of
  // `step` cannot tell: most tracks move as their neighbours do.
  bool departs(const Eigen::Vector2d& at, std::size_t skip, std::size_t min_tracks,
               const Eigen::Vector2d& step, double max_deviation) const;

 private:
  // A place's cell along each axis, clamped into the grid (every finite start lies inside it);
  // never decreasing with the place, so the cells of a range's ends bound those within it.
  int column(double x) const;
  int row(double y) const;
  int clamped_cell(double offset, int cells) const;

  // The steps of the tracks within the radius of `at`, but `skip`: the first `count` of xs and of
  // ys (the storage has room for every track of the cells read).
  struct Neighbours {
    std::vector<double> storage;
    double* xs = nullptr;
    double* ys = nullptr;
    std::size_t count = 0;
  };
  Neighbours neighbours(const Eigen::Vector2d& at, std::size_t skip) const;

  std::vector<Eigen::Vector2d> starts_, steps_;
  double radius_;
  double cell_size_ = 0;  // at least radius_
  Eigen::Vector2d origin_{0, 0};
  int columns_ = 0, rows_ = 0;
  // Tracks by cell: cell c's tracks are by_cell_[cell_begin_[c] .. cell_begin_[c + 1]).
  std::vector<std::size_t> cell_begin_, by_cell_;
};

}  // namespace omnisfm::track
