#pragma once
// The percentiles that reports and plots quote (median, 95th) of a set of errors.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace omnisfm::core {

// The value below which `fraction` of the values in [begin, end) lie: the sorted values' entry
// floor(fraction n) (counted from 0; for the median of an even count the upper middle one); 0 for
// none. Reorders them: for loops that would otherwise copy them each time.
inline double percentile_in_place(double* begin, double* end, double fraction) {
  if (begin == end) return 0;
  const size_t n = static_cast<size_t>(end - begin);
  const size_t k = std::min(n - 1, static_cast<size_t>(fraction * n));
  std::nth_element(begin, begin + k, end);
  return begin[k];
}

// The same, of *values.
inline double percentile_in_place(std::vector<double>* values, double fraction) {
  return percentile_in_place(values->data(), values->data() + values->size(), fraction);
}

// The same, of a copy.
inline double percentile(std::vector<double> values, double fraction) {
  return percentile_in_place(&values, fraction);
}

}  // namespace omnisfm::core
