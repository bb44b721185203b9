#include "omnisfm/core/solver_threads.h"

#include <gtest/gtest.h>

#include <thread>

namespace omnisfm::core {
namespace {

TEST(SolverThreads, TheCallersCountElseOneForASmallProblemElseOnePerCore) {
  EXPECT_EQ(solver_threads(3, 10), 3);
  EXPECT_EQ(solver_threads(1, 1000000), 1);
  EXPECT_EQ(solver_threads(0, 0), 1);
  EXPECT_EQ(solver_threads(0, kSmallProblemResiduals - 1), 1);
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  EXPECT_EQ(solver_threads(0, kSmallProblemResiduals), cores);
}

}  // namespace
}  // namespace omnisfm::core
