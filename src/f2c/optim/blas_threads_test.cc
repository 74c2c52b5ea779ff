#include "f2c/optim/blas_threads.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <initializer_list>

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

// ... and CHOLMOD's OpenMP regions on the thread that meets them.
TEST(BlasThreads, ASolveLeavesOpenMpRegionsSerial) {
  if (OpenMpMaxActiveLevels() < 0) GTEST_SKIP() << "no OpenMP runtime is loaded here";
  for (const char* name : {"OMP_NUM_THREADS", "OMP_THREAD_LIMIT", "OMP_MAX_ACTIVE_LEVELS"}) {
    if (std::getenv(name) != nullptr) GTEST_SKIP() << name << " is set: left to it";
  }
  PoseVector poses(2);
  poses[1].translation.x() = 1;
  SolvePoses({}, SolverOptions(), &poses);
  EXPECT_EQ(OpenMpMaxActiveLevels(), 0);
}

}  // namespace
}  // namespace f2c
