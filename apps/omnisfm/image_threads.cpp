#include "image_threads.h"

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdlib>
#include <opencv2/core.hpp>
#include <string>

#include "omnisfm/io/input_error.h"

namespace omnisfm::app {

int image_threads_setting() {
  const char* text = std::getenv("OMNISFM_THREADS");
  if (text == nullptr || *text == '\0') return 0;
  char* end = nullptr;
  errno = 0;
  const long count = std::strtol(text, &end, 10);
  if (*end != '\0' || errno != 0 || count < 1 || count > 1024)
    throw CLI::ValidationError(
        "OMNISFM_THREADS", "'" + io::printable_text(text) + "' is not a count of threads (1-1024)");
  return static_cast<int>(count);
}

void apply_image_threads() {
  if (const int count = image_threads_setting(); count > 0) cv::setNumThreads(count);
}

int renderer_threads() {
  const int count = image_threads_setting();
  return count > 0 ? count : 2;
}

}  // namespace omnisfm::app
