#include "f2c/odometry/odometry.h"

#include <gtest/gtest.h>

#include <map>
#include <mutex>

#include "f2c/eval/trajectory_error.h"
#include "f2c/io/image.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/error.h"

namespace f2c {
namespace {

using testing::SyntheticScene;
using testing::TestIntrinsics;
using Poses = std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>;

// A hand-held-like sweep: 3 cm and 1.5 degrees of yaw per frame.
Poses Sweep(int n) {
  Poses poses;
  for (int i = 0; i < n; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(0.026 * i, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(0.01 * std::sin(i), Eigen::Vector3d::UnitX()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.03 * i, 0.005 * std::sin(0.7 * i), -0.8 + 0.01 * i);
    poses.push_back(pose);
  }
  return poses;
}

RgbdSequence WriteAndRead(const std::string& name, const SyntheticScene& scene, int n) {
  const auto dir = testing::FreshTempDir(name);
  testing::WriteTumSequence(dir, scene, TestIntrinsics(), Sweep(n));
  IoOptions io;
  io.intrinsics = "525,525,319.5,239.5";
  return ReadSequence(dir, io);
}

// Relative motions of T0 must match the rendered poses (T0[0] = identity, so compare the
// chain, not absolute poses).
void ExpectMatchesTruth(const Odometry& odometry, const Poses& truth, double max_t, double max_r) {
  ASSERT_EQ(odometry.t0.size(), truth.size());
  EXPECT_TRUE(odometry.t0.world_from_camera[0].matrix().isIdentity());
  for (size_t i = 1; i < truth.size(); ++i) {
    const Rigid3d expected = truth[0].inverse() * truth[i];
    const Rigid3d& got = odometry.t0.world_from_camera[i];
    EXPECT_LT((got.translation() - expected.translation()).norm(), max_t) << "frame " << i;
    EXPECT_LT(RotationAngle(got.linear().transpose() * expected.linear()), max_r) << "frame " << i;
  }
}

TEST(AlignConsecutive, TexturedSceneRecoversTheTrajectoryWithSift) {
  const SyntheticScene scene;
  const RgbdSequence seq = WriteAndRead("odometry_textured", scene, 6);
  OdometryRun run;
  run.quiet = true;
  const Odometry odometry = AlignConsecutive(seq, OdometryOptions(), run);
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kSift) << "frame " << pair.frame;
    EXPECT_GT(pair.inliers, 50);
    EXPECT_GT(pair.fitness, 0.95);
  }
  ExpectMatchesTruth(odometry, Sweep(6), 0.01, 0.005);
}

TEST(AlignConsecutive, TexturelessSceneFallsBackToIcp) {
  SyntheticScene scene;
  scene.textured = false;
  const RgbdSequence seq = WriteAndRead("odometry_textureless", scene, 4);
  OdometryRun run;
  run.quiet = true;
  const Odometry odometry = AlignConsecutive(seq, OdometryOptions(), run);
  for (const PairAlignment& pair : odometry.pairs) EXPECT_EQ(pair.method, AlignmentMethod::kIcp);
  ExpectMatchesTruth(odometry, Sweep(4), 0.02, 0.01);
}

TEST(AlignConsecutive, WithoutFallbackTexturelessPairsAssumeThePreviousMotion) {
  SyntheticScene scene;
  scene.textured = false;
  const RgbdSequence seq = WriteAndRead("odometry_prior", scene, 3);
  OdometryOptions options;
  options.icp_fallback = false;
  OdometryRun run;
  run.quiet = true;
  const Odometry odometry = AlignConsecutive(seq, options, run);
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kMotionPrior);
    EXPECT_TRUE(pair.prev_from_curr.matrix().isIdentity());  // no motion known before frame 1
  }
}

TEST(AlignConsecutive, CacheIsReusedAndGivesTheSameAnswer) {
  const SyntheticScene scene;
  const RgbdSequence seq = WriteAndRead("odometry_cache", scene, 4);
  OdometryRun run;
  run.quiet = true;
  run.cache_file = testing::FreshTempDir("odometry_cache_out") / "cache" / "pairs.json";
  const Odometry first = AlignConsecutive(seq, OdometryOptions(), run);
  EXPECT_EQ(first.timings.pairs_cached, 0);
  const Odometry second = AlignConsecutive(seq, OdometryOptions(), run);
  EXPECT_EQ(second.timings.pairs_cached, 3);
  EXPECT_EQ(second.timings.frames_processed, 0);
  for (size_t i = 0; i < first.t0.size(); ++i) {
    EXPECT_LT((first.t0.world_from_camera[i].matrix() - second.t0.world_from_camera[i].matrix()).norm(), 1e-12);
  }
  OdometryOptions other;
  other.ratio = 0.6;  // another option: nothing may come from the cache
  EXPECT_EQ(AlignConsecutive(seq, other, run).timings.pairs_cached, 0);
}

// Every decoded depth image is handed to on_depth once, as LoadDepthMeters decodes it, even
// across chunk borders (where a chunk reuses the previous chunk's last frame).
TEST(AlignConsecutive, HandsEachDecodedDepthImageOverOnce) {
  const SyntheticScene scene;
  const RgbdSequence seq = WriteAndRead("odometry_on_depth", scene, 5);
  OdometryRun run;
  run.quiet = true;
  run.chunk_frames = 2;
  std::mutex mutex;
  std::map<int, cv::Mat> seen;
  int calls = 0;
  run.on_depth = [&](int frame, const cv::Mat& depth) {
    std::lock_guard<std::mutex> lock(mutex);
    ++calls;
    seen[frame] = depth.clone();
  };
  AlignConsecutive(seq, OdometryOptions(), run);
  EXPECT_EQ(calls, 5);
  ASSERT_EQ(seen.size(), 5u);
  for (const auto& [frame, depth] : seen) {
    EXPECT_EQ(cv::norm(depth, LoadDepthMeters(seq, seq.frames[frame]), cv::NORM_INF), 0.0) << frame;
  }
}

TEST(AlignConsecutive, SameInputSamePoses) {
  const SyntheticScene scene;
  const RgbdSequence seq = WriteAndRead("odometry_determinism", scene, 4);
  OdometryRun run;
  run.quiet = true;
  run.chunk_frames = 2;  // chunk borders must not change the answer either
  const Odometry a = AlignConsecutive(seq, OdometryOptions(), run);
  run.chunk_frames = 64;
  const Odometry b = AlignConsecutive(seq, OdometryOptions(), run);
  for (size_t i = 0; i < a.t0.size(); ++i) {
    EXPECT_EQ(a.t0.world_from_camera[i].matrix(), b.t0.world_from_camera[i].matrix());
  }
}

// With min_fitness = 1 every SIFT answer is checked against ICP; the answer kept must fit the
// depth images at least as well as SIFT's alone, and the trajectory must stay right.
TEST(AlignConsecutive, FitnessCheckKeepsTheBetterFittingAnswer) {
  const SyntheticScene scene;
  const RgbdSequence seq = WriteAndRead("odometry_fitness_check", scene, 4);
  OdometryRun run;
  run.quiet = true;
  OdometryOptions sift_only;
  sift_only.min_fitness = 0.0;
  OdometryOptions checked;
  checked.min_fitness = 1.0;
  const Odometry a = AlignConsecutive(seq, sift_only, run);
  const Odometry b = AlignConsecutive(seq, checked, run);
  for (size_t i = 0; i < a.pairs.size(); ++i) {
    EXPECT_EQ(a.pairs[i].method, AlignmentMethod::kSift);
    EXPECT_GE(b.pairs[i].fitness, a.pairs[i].fitness) << "pair " << i;
    if (b.pairs[i].method == AlignmentMethod::kSift) {
      EXPECT_EQ(b.pairs[i].prev_from_curr.matrix(), a.pairs[i].prev_from_curr.matrix());
    }
  }
  ExpectMatchesTruth(b, Sweep(4), 0.01, 0.005);
}

TEST(AlignConsecutive, MissingIntrinsicsIsAnInputError) {
  const SyntheticScene scene;
  const auto dir = testing::FreshTempDir("odometry_no_k");
  testing::WriteTumSequence(dir, scene, TestIntrinsics(), Sweep(2));
  const RgbdSequence seq = ReadSequence(dir);
  try {
    AlignConsecutive(seq, OdometryOptions());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir.string() + ": no intrinsics: pass --intrinsics (a preset: "
                                                     "tum-fr1, tum-fr2, tum-fr3, primesense; or fx,fy,cx,cy)");
  }
}

}  // namespace
}  // namespace f2c
