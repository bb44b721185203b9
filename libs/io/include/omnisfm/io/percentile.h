#pragma once
// The percentiles that reports and plots quote (median, 95th) of a set of errors.

#include <vector>

namespace omnisfm::io {

// The value below which `fraction` of `values` lie (nearest rank, the lower one); 0 for none.
double percentile(std::vector<double> values, double fraction);

}  // namespace omnisfm::io
