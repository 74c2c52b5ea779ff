#include "f2c/io/image_write.h"
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

// The prior is the previous pair's motion, not identity: the first pair is aligned by SIFT,
// then the colour goes blank (no keypoints) and, without ICP, each later pair repeats it.
TEST(AlignConsecutive, WithoutFallbackTheLastMeasuredMotionIsPassedOn) {
  const RgbdSequence seq = WriteAndRead("odometry_prior_passed", SyntheticScene(), 4);
  const cv::Mat blank(480, 640, CV_8UC3, cv::Scalar(128, 128, 128));
  for (int i : {2, 3}) WritePngFile(seq.frames[i].color_path, blank);
  OdometryOptions options;
  options.icp_fallback = false;
  OdometryRun run;
  run.quiet = true;
  const Odometry odometry = AlignConsecutive(seq, options, run);
  ASSERT_EQ(odometry.pairs.size(), 3u);
  EXPECT_EQ(odometry.pairs[0].method, AlignmentMethod::kSift);
  const Rigid3d& measured = odometry.pairs[0].prev_from_curr;
  EXPECT_GT(measured.translation().norm(), 0.02);  // the sweep's 3 cm per frame
  for (int k : {1, 2}) {
    EXPECT_EQ(odometry.pairs[k].method, AlignmentMethod::kMotionPrior) << k;
    EXPECT_TRUE(odometry.pairs[k].prev_from_curr.isApprox(measured, 1e-9)) << k;
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
    EXPECT_EQ(std::string(e.what()), dir.string() +
                                         ": no intrinsics: pass --intrinsics (a preset: "
                                         "tum-fr1, tum-fr2, tum-fr3, primesense; or fx,fy,cx,cy)");
  }
}

}  // namespace
}  // namespace f2c

namespace f2c {
namespace {

Rigid3d Motion(double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& t) {
  Rigid3d m = Rigid3d::Identity();
  m.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  m.translation() = t;
  return m;
}

// PriorAge counts the pairs in a row before the given one that left directions to the motion
// prior: motion-prior pairs and ICP pairs with a degenerate direction; a measured pair (SIFT,
// or ICP that measured everything) ends the run.
TEST(PriorAge, CountsThePairsInARowLeftToThePrior) {
  std::vector<PairAlignment> pairs(6);
  pairs[0].method = AlignmentMethod::kIcp, pairs[0].degenerate = 1;
  pairs[1].method = AlignmentMethod::kSift;
  pairs[2].method = AlignmentMethod::kIcp, pairs[2].degenerate = 2;
  pairs[3].method = AlignmentMethod::kMotionPrior;
  pairs[4].method = AlignmentMethod::kIcp, pairs[4].degenerate = 0;
  pairs[5].method = AlignmentMethod::kIcp, pairs[5].degenerate = 3;
  const std::vector<int> expected = {0, 1, 0, 1, 2, 0, 1};
  for (int i = 0; i <= 6; ++i) EXPECT_EQ(PriorAge(pairs, i), expected[i]) << i;
}

// T0 chains each frame onto its reference's pose, whether the reference is the previous frame
// or an earlier keyframe, and keeps the frames' timestamps.
TEST(ConcatenatePairs, ChainsEachFrameOntoItsReference) {
  RgbdSequence seq;
  seq.frames.resize(4);
  for (int i = 0; i < 4; ++i) seq.frames[i].timestamp = 10.0 + i;
  const Rigid3d a = Motion(0.1, {0, 1, 0}, {0.1, 0, 0});
  const Rigid3d b = Motion(-0.2, {1, 0, 1}, {0, 0.05, 0.02});
  const Rigid3d c = Motion(0.3, {0, 0, 1}, {-0.1, 0.2, 0});
  std::vector<PairAlignment> pairs(3);
  pairs[0].frame = 1, pairs[0].reference = 0, pairs[0].prev_from_curr = a;
  pairs[1].frame = 2, pairs[1].reference = 1, pairs[1].prev_from_curr = b;
  pairs[2].frame = 3, pairs[2].reference = 1, pairs[2].prev_from_curr = c;  // frame 1 is its keyframe
  const Trajectory t0 = ConcatenatePairs(seq, pairs);
  ASSERT_EQ(t0.size(), 4u);
  EXPECT_TRUE(t0.world_from_camera[0].isApprox(Rigid3d::Identity()));
  EXPECT_TRUE(t0.world_from_camera[1].isApprox(a, 1e-12));
  EXPECT_TRUE(t0.world_from_camera[2].isApprox(a * b, 1e-12));
  EXPECT_TRUE(t0.world_from_camera[3].isApprox(a * c, 1e-12));
  EXPECT_FALSE(t0.world_from_camera[3].isApprox(a * b * c, 1e-3));
  EXPECT_DOUBLE_EQ(t0.timestamps[3], 13.0);
  // A pair list that does not match the frames is our bug, not the user's input.
  pairs.pop_back();
  EXPECT_THROW(ConcatenatePairs(seq, pairs), InternalError);
  pairs.push_back(PairAlignment{});
  pairs[2].frame = 3, pairs[2].reference = 3;
  EXPECT_THROW(ConcatenatePairs(seq, pairs), InternalError);
}

// A camera on a screw path (a constant velocity: 2 degrees and 2 cm per 1/30 s), whose colour
// images were taken a varying 12 ms before or after its depth images. Pairs measured between
// the colour moments, referred to the depth moments by the motion T0 shows, agree with the
// depth moments' true relative poses many times better than before; an ICP pair (measured
// from depth) is left as it was, and so is a sequence whose two images share their moments.
TEST(ReferColorToDepthMoments, PairsMeasuredFromColourMoveToTheDepthsMoments) {
  const double frame_s = 1.0 / 30.0;
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1.0, 0.2).normalized();
  Rigid3d offset = Rigid3d::Identity();
  offset.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()).toRotationMatrix();
  offset.translation() = Eigen::Vector3d(0.2, -0.1, 0.5);
  const auto world_from_camera = [&](double t) {
    Rigid3d screw = Rigid3d::Identity();
    screw.linear() = Eigen::AngleAxisd(0.035 / frame_s * t, axis).toRotationMatrix();
    screw.translation() = 0.02 / frame_s * t * axis;
    return Rigid3d(screw * offset);
  };
  const int n = 20;
  RgbdSequence seq;
  for (int k = 0; k < n; ++k) {
    RgbdFrame f;
    f.timestamp = k * frame_s;
    f.color_time = 0.012 * std::cos(0.3 * k);
    seq.frames.push_back(f);
  }
  Odometry odometry;
  for (int k = 1; k < n; ++k) {
    PairAlignment p;
    p.frame = k;
    p.reference = k - 1;
    p.method = k == 7 ? AlignmentMethod::kIcp : AlignmentMethod::kTrack;
    const double tc = seq.frames[k].timestamp + seq.frames[k].color_time;
    const double tr = seq.frames[k - 1].timestamp + seq.frames[k - 1].color_time;
    p.prev_from_curr = world_from_camera(tr).inverse() * world_from_camera(tc);  // what colour measured
    odometry.pairs.push_back(p);
  }
  odometry.t0 = ConcatenatePairs(seq, odometry.pairs);
  Odometry same_moments = odometry;
  const std::vector<PairAlignment> measured = odometry.pairs;
  ReferColorToDepthMoments(seq, &odometry);
  ASSERT_EQ(odometry.depth_from_color.size(), static_cast<size_t>(n));
  double before = 0, after = 0;
  for (int k = 1; k < n; ++k) {
    const Rigid3d truth =
        world_from_camera(seq.frames[k - 1].timestamp).inverse() * world_from_camera(seq.frames[k].timestamp);
    const auto error = [&](const Rigid3d& pair) {
      const Rigid3d e = truth.inverse() * pair;
      return e.translation().norm() + RotationAngle(e.linear());  // metres + radians, at 1 m
    };
    if (k == 7) {
      EXPECT_TRUE(odometry.pairs[k - 1].prev_from_curr.isApprox(measured[k - 1].prev_from_curr, 0)) << "ICP pair moved";
      continue;
    }
    before += error(measured[k - 1].prev_from_curr);
    after += error(odometry.pairs[k - 1].prev_from_curr);
  }
  // The offset changes by up to 7 ms over a frame's two neighbours: the velocity from T0 is off
  // by up to about an eighth, and what remains of the error with it.
  EXPECT_GT(before, 0.01);
  EXPECT_LT(after, 0.25 * before);
  // T0 chained again from the moved pairs.
  EXPECT_TRUE(odometry.t0.world_from_camera[5].isApprox(
      odometry.t0.world_from_camera[4] * odometry.pairs[4].prev_from_curr, 1e-9));

  for (RgbdFrame& f : seq.frames) f.color_time = 0;
  ReferColorToDepthMoments(seq, &same_moments);
  EXPECT_TRUE(same_moments.depth_from_color.empty());
  for (size_t i = 0; i < measured.size(); ++i) {
    EXPECT_TRUE(same_moments.pairs[i].prev_from_curr.isApprox(measured[i].prev_from_curr, 0)) << i;
  }
}

}  // namespace
}  // namespace f2c
