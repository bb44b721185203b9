#pragma once
// The threads the command's image work runs on: OpenCV's (corner detection, tracking) and the
// renderer's. OMNISFM_THREADS=N sets them; unset, OpenCV takes one per core and the renderer two.
// Where the cores are busy with other work (a test suite running programs side by side), OpenCV's
// waiting threads spin and cost more than they give: calibrating from the vmr set's images took
// 38 % more processor time on two threads than on one, in the same wall time.

namespace omnisfm::app {

// OMNISFM_THREADS as a count of 1 or more, or 0 where it is unset or empty. Throws
// CLI::ValidationError naming the variable where it holds anything else.
int image_threads_setting();

// Gives OpenCV the count OMNISFM_THREADS sets, where it sets one.
void apply_image_threads();

// The renderer's threads: OMNISFM_THREADS's count, else 2.
int renderer_threads();

}  // namespace omnisfm::app
