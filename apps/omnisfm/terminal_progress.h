#pragma once
// Progress of long work on stderr, "omnisfm: WHAT done/all UNIT" rewritten in place every tenth
// step and at the last, only when stderr is a terminal (a log file gets none of it).

#include <functional>
#include <string>

namespace omnisfm::app {

class TerminalProgress {
 public:
  // what: e.g. "filter" or "lab: rendered"; unit: e.g. "frames".
  TerminalProgress(std::string what, std::string unit);
  // Ends the line if it is still open (the work stopped short of its total, or threw).
  ~TerminalProgress();
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  // all <= 0: the total is not known (a video's frames). The line ends once done reaches all.
  void operator()(int done, int all);
  // For the libraries' progress callbacks; this object must outlive it.
  std::function<void(int, int)> callback() {
    return [this](int done, int all) { (*this)(done, all); };
  }

 private:
  std::string what_, unit_;
  bool terminal_;
  bool line_open_ = false;
};

}  // namespace omnisfm::app
