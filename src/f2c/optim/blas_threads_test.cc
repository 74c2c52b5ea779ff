#include "f2c/optim/blas_threads.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "f2c/optim/problem.h"

namespace f2c {
namespace {

// Any solve leaves OpenBLAS (loaded through Ceres' LAPACK and CHOLMOD) on one thread.
TEST(BlasThreads, ASolveLeavesOpenBlasOnOneThread) {
  if (BlasThreads() < 0) GTEST_SKIP() << "OpenBLAS is not the BLAS loaded here";
  if (std::getenv("OPENBLAS_NUM_THREADS") != nullptr) GTEST_SKIP() << "OPENBLAS_NUM_THREADS is set: left to it";
  PoseVector poses(2);
  poses[1].translation.x() = 1;
  SolvePoses({}, SolverOptions(), &poses);
  EXPECT_EQ(BlasThreads(), 1);
  EXPECT_TRUE(UseOneBlasThread());
}

}  // namespace
}  // namespace f2c
