// The pipeline as one call: a simulated scan registered end to end (its cache reused by a
// second call), the files written from the typed result, bad options, and a real sequence
// from ../shared/data (skipped when absent).

#include "f2c/pipeline/register.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "f2c/eval/trajectory_error.h"
#include "f2c/io/trajectory.h"
#include "f2c/pipeline/outputs.h"
#include "f2c/sim/simulate.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

double Ate(const Trajectory& estimate, const Trajectory& truth) {
  return Evaluate(estimate, truth).ate.translation.rmse;
}

// The first `frames` frames (30 a second) of a walk through two rooms, with sensor noise.
fs::path SimulatedWalk(int frames) {
  const fs::path dir = testing::FreshTempDir("register_walk_" + std::to_string(frames)) / "scan";
  sim::SimulateOptions o;
  o.scene = "two-rooms";
  o.seed = 1;
  o.walk.frames = frames;
  o.correspondences = 0;
  sim::Simulate(dir, o, /*quiet=*/true);
  return dir;
}

TEST(Register, RefinesASimulatedWalkAndReusesItsCache) {
  const fs::path scan = SimulatedWalk(60), out = scan.parent_path() / "out";
  RegisterOptions options;
  options.quiet = true;
  options.cache_dir = out / "cache";
  options.fusion.tsdf.voxel_size = 0.04;
  std::map<std::string, std::pair<long, long>> heard;  // stage: last (done, total)
  options.progress = [&](const std::string& stage, long done, long total) { heard[stage] = {done, total}; };
  const RegisterResult first = Register(scan, IoOptions(), options);

  ASSERT_EQ(first.sequence.frames.size(), 60u);
  ASSERT_TRUE(first.sequence.ground_truth);
  ASSERT_TRUE(first.refine);
  const double t0 = Ate(first.odometry.t0, *first.sequence.ground_truth);
  const double refined = Ate(first.poses, *first.sequence.ground_truth);
  EXPECT_LT(refined, 0.5 * t0) << "T0 " << t0 << " m, refined " << refined << " m";
  std::printf("ATE: T0 %.4f m, refined %.4f m\n", t0, refined);
  EXPECT_FALSE(first.refine->result.iterations.empty());
  ASSERT_TRUE(first.fusion);
  EXPECT_GT(first.fusion->mesh.faces.size(), 1000u);
  EXPECT_EQ(first.odometry_counts.pairs, 59);
  EXPECT_EQ(first.features->timings.frames_computed, 60);
  // Each stage told the listener of its end.
  for (const char* stage : {"odometry", "refine", "fusion"}) {
    ASSERT_TRUE(heard.count(stage)) << stage;
    EXPECT_EQ(heard[stage].first, heard[stage].second) << stage;
  }
  EXPECT_EQ(heard["fusion"].second, 60);

  // Again, from the cache: every frame's features read back, the same poses to the bit (no
  // mesh: the first run's was checked).
  RegisterOptions again = options;
  again.progress = nullptr;
  again.fuse_mesh = false;
  const RegisterResult second = Register(scan, IoOptions(), again);
  EXPECT_EQ(second.features->timings.frames_cached, 60);
  EXPECT_EQ(second.features->timings.frames_computed, 0);
  ASSERT_EQ(second.poses.size(), first.poses.size());
  double most = 0;
  for (size_t k = 0; k < first.poses.size(); ++k) {
    most = std::max(
        most,
        (second.poses.world_from_camera[k].matrix() - first.poses.world_from_camera[k].matrix()).cwiseAbs().maxCoeff());
  }
  // Bit for bit: a cached pair is the computed one (its information matrix whole, not its
  // upper triangle, which differed from the computed one in the last bit).
  EXPECT_EQ(most, 0.0);

  // The files, from the typed result.
  OutputOptions outputs;
  outputs.report = false;
  const std::vector<std::string> names = WriteOutputs(out, first, options, outputs);
  const nlohmann::json run = nlohmann::json::parse(ReadFileToString(out / "run.json"));
  EXPECT_EQ(run["outputs"], nlohmann::json(names));
  for (const std::string& name : names) EXPECT_TRUE(fs::exists(out / name)) << name;
  EXPECT_EQ(run["result"], "refined");
  EXPECT_EQ(run["frames"], 60);
  EXPECT_EQ(run["stages"]["refine"]["iterations"].size(), first.refine->result.iterations.size());
  EXPECT_EQ(run["statistics"]["odometry"]["pairs"], 59);
  const Trajectory written = ReadTrajectoryFile(out / "trajectory.txt");
  ASSERT_EQ(written.size(), first.poses.size());
  EXPECT_LT(
      (written.world_from_camera.back().translation() - first.poses.world_from_camera.back().translation()).norm(),
      1e-5);
  EXPECT_NEAR(Ate(ReadTrajectoryFile(out / "trajectory_t0.txt"), *first.sequence.ground_truth), t0, 1e-5);
}

TEST(Register, OdometryOnlyGivesT0) {
  RegisterOptions options;
  options.quiet = true;
  options.refine_poses = false;
  options.fuse_mesh = false;
  const RegisterResult r = Register(SimulatedWalk(12), IoOptions(), options);
  EXPECT_FALSE(r.refine);
  EXPECT_FALSE(r.fusion);
  ASSERT_EQ(r.poses.size(), 12u);
  for (size_t k = 0; k < r.poses.size(); ++k) {
    EXPECT_TRUE(r.poses.world_from_camera[k].isApprox(r.odometry.t0.world_from_camera[k], 0.0));
  }
  const nlohmann::json run = RunJson(r, options, OutputOptions());
  EXPECT_EQ(run["result"], "t0");
  EXPECT_TRUE(run["stages"]["refine"].is_null());
  EXPECT_TRUE(run["options"]["refine"].is_null());
}

TEST(Register, BadOptionsAreOneLineBeforeAnyWork) {
  RegisterOptions options;
  options.threads = 5000;
  EXPECT_EQ(testing::InputErrorMessage([&] { Register(fs::path("/nonexistent"), IoOptions(), options); }),
            "--threads: must be in [0, 1024], got 5000");
  options.threads = 0;
  options.refine_poses = false;
  options.initial_poses = PoseList(3, Rigid3d::Identity());
  EXPECT_EQ(testing::InputErrorMessage([&] { options.Check(); }),
            "--initial-trajectory: only the refinement starts from it, and --stop-after odometry skips the refinement");
  options.refine_poses = true;
  EXPECT_EQ(testing::InputErrorMessage([&] { Register(SimulatedWalk(10), IoOptions(), options); }),
            "--initial-trajectory: 3 poses for 10 frames");
}

// The whole pipeline on the first 200 frames of fr1/xyz (13 s of hand-held motion over a
// desk, motion-capture ground truth).
TEST(Register, RefinementCutsT0sErrorOnFr1Xyz) {
  const fs::path path = fs::path(F2C_SHARED_DATA_DIR) / "tum_fr1_xyz_15hz";
  if (!fs::exists(path)) GTEST_SKIP() << "../shared/data absent";
  IoOptions io;
  io.intrinsics = "tum-fr1";
  io.last = 119;
  RegisterOptions options;
  options.quiet = true;
  options.fuse_mesh = false;
  const RegisterResult r = Register(path, io, options);
  const double before = Ate(r.odometry.t0, *r.sequence.ground_truth);
  const double after = Ate(r.poses, *r.sequence.ground_truth);
  // Measured on these 120 frames: T0 (keyframe odometry) 0.0187 m, refined 0.0147 m.
  EXPECT_LT(after, 0.85 * before) << "T0 " << before << " m, refined " << after << " m";
  EXPECT_LT(after, 0.016);
}

}  // namespace
}  // namespace f2c
