#pragma once
// Plots drawn by gnuplot from a script beside their data, so that a user can redraw them.

#include <string>

namespace omnisfm::io {

// Runs gnuplot on `script`, a file in `folder`, from that folder. Its messages go to
// `script`.log, which is removed when it succeeds. False when gnuplot is missing or fails.
bool run_gnuplot(const std::string& folder, const std::string& script);

// A tidy plot scale: 1, 2 or 5 times a power of ten, at most `value` (> 0).
double round_down_125(double value);

}  // namespace omnisfm::io
