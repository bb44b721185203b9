#include "terminal_progress.h"

#include <unistd.h>

#include <iostream>
#include <utility>

namespace omnisfm::app {

TerminalProgress::TerminalProgress(std::string what, std::string unit)
    : what_(std::move(what)), unit_(std::move(unit)), terminal_(::isatty(STDERR_FILENO) != 0) {}

TerminalProgress::~TerminalProgress() {
  if (line_open_) std::cerr << "\n" << std::flush;
}

void TerminalProgress::operator()(int done, int all) {
  const bool last = all > 0 && done >= all;
  if (!terminal_ || (done % 10 != 0 && !last)) return;
  std::cerr << "\romnisfm: " << what_ << " " << done;
  if (all > 0) std::cerr << "/" << all;
  std::cerr << " " << unit_;
  line_open_ = !last;
  if (last) std::cerr << "\n";
  std::cerr << std::flush;
}

}  // namespace omnisfm::app
