#pragma once
// Normalised estimation errors squared, tallied: their mean and the share inside a chi-square
// bound (for a consistent estimator, the degrees of freedom and the bound's probability).

#include <cstddef>

namespace omnisfm::mrpt_plugin {

class NeesTally {
 public:
  explicit NeesTally(double bound) : bound_(bound) {}
  void add(double nees) {
    sum_ += nees;
    inside_ += nees <= bound_;
    ++count_;
  }
  double mean() const { return count_ ? sum_ / static_cast<double>(count_) : 0; }
  double inside() const { return count_ ? static_cast<double>(inside_) / count_ : 0; }
  std::size_t count() const { return count_; }

 private:
  double bound_;
  double sum_ = 0;
  std::size_t inside_ = 0, count_ = 0;
};

}  // namespace omnisfm::mrpt_plugin
