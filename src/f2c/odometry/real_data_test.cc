// Odometry on real sequences from ../shared/data (skipped when absent).

#include <gtest/gtest.h>

#include <filesystem>

#include "f2c/eval/trajectory_error.h"
#include "f2c/odometry/odometry.h"

namespace f2c {
namespace {

std::filesystem::path Data(const std::string& name) {
  return std::filesystem::path(F2C_SHARED_DATA_DIR) / name;
}

TEST(RealData, TumFr1XyzFirst80FramesT0WithinFiveCentimetres) {
  if (!std::filesystem::exists(Data("tum_fr1_xyz_15hz"))) GTEST_SKIP() << "../shared/data absent";
  IoOptions io;
  io.intrinsics = "tum-fr1";
  io.last = 79;
  const RgbdSequence seq = ReadSequence(Data("tum_fr1_xyz_15hz"), io);
  OdometryRun run;
  run.quiet = true;
  const Odometry odometry = AlignConsecutive(seq, OdometryOptions(), run);
  const EvaluationResult r = Evaluate(odometry.t0, *seq.ground_truth);
  EXPECT_EQ(r.ate.translation.count, 80);
  EXPECT_LT(r.ate.translation.rmse, 0.05);
  EXPECT_LT(r.rpe_per_frame.translation.rmse, 0.02);
  EXPECT_LT(r.rpe_per_frame.rotation.rmse, 1.0);
  for (const PairAlignment& p : odometry.pairs) EXPECT_EQ(p.method, AlignmentMethod::kSift);
}

TEST(RealData, TumFr1DeskNineFramesAlign) {
  if (!std::filesystem::exists(Data("tum_fr1_desk_9"))) GTEST_SKIP() << "../shared/data absent";
  IoOptions io;
  io.intrinsics = "tum-fr1";
  const RgbdSequence seq = ReadSequence(Data("tum_fr1_desk_9"), io);
  OdometryRun run;
  run.quiet = true;
  const Odometry odometry = AlignConsecutive(seq, OdometryOptions(), run);
  const EvaluationResult r = Evaluate(odometry.t0, *seq.ground_truth);
  EXPECT_EQ(r.ate.translation.count, 9);
  EXPECT_LT(r.ate.translation.rmse, 0.03);
}

}  // namespace
}  // namespace f2c
