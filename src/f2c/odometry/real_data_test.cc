// Odometry on real sequences from ../shared/data (skipped when absent).

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "f2c/eval/trajectory_error.h"
#include "f2c/odometry/odometry.h"

namespace f2c {
namespace {

std::filesystem::path Data(const std::string& name) { return std::filesystem::path(F2C_SHARED_DATA_DIR) / name; }

// T0 of the first `frames` frames of a TUM fr1 folder, and its error against motion capture.
struct T0Run {
  Odometry odometry;
  EvaluationResult error;
};
T0Run RunT0(const std::string& name, int frames) {
  IoOptions io;
  io.intrinsics = "tum-fr1";
  io.last = frames - 1;
  const RgbdSequence seq = ReadSequence(Data(name), io);
  OdometryRun run;
  run.quiet = true;
  T0Run result;
  result.odometry = AlignConsecutive(seq, OdometryOptions(), run);
  result.error = Evaluate(result.odometry.t0, *seq.ground_truth);
  return result;
}

TEST(RealData, TumFr1XyzFirst80FramesT0WithinFiveCentimetres) {
  if (!std::filesystem::exists(Data("tum_fr1_xyz_15hz"))) GTEST_SKIP() << "../shared/data absent";
  const T0Run t0 = RunT0("tum_fr1_xyz_15hz", 80);
  const Odometry& odometry = t0.odometry;
  const EvaluationResult& r = t0.error;
  EXPECT_EQ(r.ate.translation.count, 80);
  EXPECT_LT(r.ate.translation.rmse, 0.05);
  EXPECT_LT(r.rpe_per_frame.translation.rmse, 0.02);
  EXPECT_LT(r.rpe_per_frame.rotation.rmse, 1.0);
  for (const PairAlignment& p : odometry.pairs) EXPECT_EQ(p.method, AlignmentMethod::kSift);
}

TEST(RealData, TumFr1DeskNineFramesAlign) {
  if (!std::filesystem::exists(Data("tum_fr1_desk_9"))) GTEST_SKIP() << "../shared/data absent";
  const EvaluationResult r = RunT0("tum_fr1_desk_9", 9).error;
  EXPECT_EQ(r.ate.translation.count, 9);
  EXPECT_LT(r.ate.translation.rmse, 0.03);
}

}  // namespace
}  // namespace f2c
