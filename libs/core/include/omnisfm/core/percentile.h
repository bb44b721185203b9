#pragma once
// The percentiles that reports and plots quote (median, 95th) of a set of errors.

#include <algorithm>
#include <vector>

namespace omnisfm::core {

// The value below which `fraction` of `values` lie: the sorted values' entry floor(fraction n)
// (counted from 0; for the median of an even count the upper middle one); 0 for none. Reorders
// *values: for loops that would otherwise copy them each time.
inline double percentile_in_place(std::vector<double>* values, double fraction) {
  if (values->empty()) return 0;
  const size_t k = std::min(values->size() - 1, static_cast<size_t>(fraction * values->size()));
  std::nth_element(values->begin(), values->begin() + k, values->end());
  return (*values)[k];
}

// The same, of a copy.
inline double percentile(std::vector<double> values, double fraction) {
  return percentile_in_place(&values, fraction);
}

}  // namespace omnisfm::core
