// Keyframe odometry on rendered scenes with known poses.

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <map>
#include <mutex>

#include "f2c/io/image.h"
#include "f2c/odometry/odometry.h"
#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

using testing::SyntheticScene;
using testing::TestIntrinsics;
using Poses = std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>;

// Yaw `degrees_per_frame` about the vertical, plus `metres_per_frame` sideways.
Poses Turn(int n, double degrees_per_frame, double metres_per_frame) {
  Poses poses;
  for (int i = 0; i < n; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = Eigen::AngleAxisd(degrees_per_frame * i * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(metres_per_frame * i, 0.0, -0.8);
    poses.push_back(pose);
  }
  return poses;
}

RgbdSequence WriteAndRead(const std::string& name, const SyntheticScene& scene, const Poses& poses, int last = -1) {
  const auto dir = testing::FreshTempDir(name);
  testing::WriteTumSequence(dir, scene, TestIntrinsics(), poses);
  IoOptions io;
  io.intrinsics = "525,525,319.5,239.5";
  io.last = last;
  return ReadSequence(dir, io);
}

RgbdSequence Reread(const RgbdSequence& seq, int last) {
  IoOptions io;
  io.intrinsics = "525,525,319.5,239.5";
  io.last = last;
  return ReadSequence(seq.root, io);
}

double AngleDeg(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle() * 180 / M_PI; }

void ExpectKeyframesMatchTruth(const Odometry& odometry, const Poses& truth, double max_t, double max_deg) {
  ASSERT_EQ(odometry.t0.size(), truth.size());
  for (size_t i = 1; i < truth.size(); ++i) {
    const Rigid3d expected = truth[0].inverse() * truth[i];
    const Rigid3d& got = odometry.t0.world_from_camera[i];
    EXPECT_LT((got.translation() - expected.translation()).norm(), max_t) << "frame " << i;
    EXPECT_LT(AngleDeg(got.linear().transpose() * expected.linear()), max_deg) << "frame " << i;
  }
}

OdometryRun Quiet() {
  OdometryRun run;
  run.quiet = true;
  return run;
}

TEST(AlignWithKeyframes, AStillCameraKeepsOneKeyframe) {
  const Poses poses(6, Turn(1, 0, 0)[0]);
  const RgbdSequence seq = WriteAndRead("keyframes_still", SyntheticScene(), poses);
  const Odometry odometry = AlignWithKeyframes(seq, OdometryOptions(), Quiet());
  EXPECT_EQ(odometry.timings.keyframes, 1);
  EXPECT_EQ(odometry.timings.sift_frames, 1);  // the keyframe's; the others are tracked
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kTrack) << pair.frame;
    EXPECT_EQ(pair.reference, 0);
    EXPECT_FALSE(pair.keyframe);
  }
  EXPECT_EQ(OdometryKeyframes(odometry), std::vector<int>{0});
  ExpectKeyframesMatchTruth(odometry, poses, 0.001, 0.05);
}

// 3 degrees per frame with a 10-degree limit: frames 1-3 (3, 6, 9 degrees) stay with
// keyframe 0, frame 4 (12) starts the next, and so on.
TEST(AlignWithKeyframes, AFastTurnStartsAKeyframeOnceItPassesTheRotationLimit) {
  const Poses poses = Turn(14, 3.0, 0.0);
  const RgbdSequence seq = WriteAndRead("keyframes_turn", SyntheticScene(), poses);
  OdometryOptions options;
  options.keyframes.max_rotation_deg = 10;
  options.keyframes.max_translation = 1.0;  // rotation alone decides here
  options.keyframes.min_overlap = 0;
  options.keyframes.min_inlier_share = 0;
  const Odometry odometry = AlignWithKeyframes(seq, options, Quiet());
  EXPECT_EQ(OdometryKeyframes(odometry), (std::vector<int>{0, 4, 8, 12}));
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kTrack) << pair.frame;
    EXPECT_EQ(pair.reference, pair.frame / 4 * 4 - (pair.frame % 4 == 0 ? 4 : 0)) << pair.frame;
  }
  ExpectKeyframesMatchTruth(odometry, poses, 0.01, 0.3);
}

// Without texture there is nothing to track or match: depth ICP aligns each frame to the
// previous one (the default), or to the keyframe (3, 6, 9 cm and 1.5, 3, 4.5 degrees away:
// all within the limits) with --icp-to-keyframe.
TEST(AlignWithKeyframes, TexturelessFramesAreAlignedByIcp) {
  SyntheticScene scene;
  scene.textured = false;
  const Poses poses = Turn(4, 1.5, 0.03);
  const RgbdSequence seq = WriteAndRead("keyframes_textureless", scene, poses);
  const Odometry odometry = AlignWithKeyframes(seq, OdometryOptions(), Quiet());
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kIcp) << pair.frame;
    EXPECT_EQ(pair.reference, pair.frame - 1);
    EXPECT_TRUE(pair.keyframe);
  }
  ExpectKeyframesMatchTruth(odometry, poses, 0.02, 0.6);
  OdometryOptions to_keyframe;
  to_keyframe.keyframes.icp_to_keyframe = true;
  const Odometry icp = AlignWithKeyframes(seq, to_keyframe, Quiet());
  for (const PairAlignment& pair : icp.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kIcp) << pair.frame;
    EXPECT_EQ(pair.reference, 0);
    EXPECT_FALSE(pair.keyframe);
  }
  EXPECT_EQ(icp.timings.sift_frames, 1);  // the keyframe has no keypoints to match: no SIFT for the others
  ExpectKeyframesMatchTruth(icp, poses, 0.02, 0.6);
}

// Facing the textured back wall from 1.5 m, sliding 1.5 cm and rolling 0.4 deg per frame about
// the wall's normal, with SIFT and tracking refused: depth ICP alone cannot see either
// motion, and keeps the prediction (no motion before the first pair); the photometric
// step (on by default) recovers both.
TEST(AlignWithKeyframes, ATexturedWallsSlideIsRecoveredFromItsImage) {
  SyntheticScene scene;
  Poses poses;
  for (int i = 0; i < 5; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(0.4 * i * M_PI / 180, Eigen::Vector3d::UnitZ()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.015 * i, 0.0, -1.0);
    poses.push_back(pose);
  }
  const RgbdSequence seq = WriteAndRead("keyframes_photometric", scene, poses);
  OdometryOptions options;
  options.min_inliers = 100000;
  options.keyframes.min_inliers = 100000;
  const Odometry odometry = AlignWithKeyframes(seq, options, Quiet());
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kIcp) << pair.frame;
    EXPECT_EQ(pair.degenerate, 0) << pair.frame;  // the image measured what the depth did not
  }
  // The roll keeps part of the prediction: the blocky texture's edges measure it less
  // firmly than the slides (AnalyseViewConstraints).
  ExpectKeyframesMatchTruth(odometry, poses, 0.003, 0.2);
  options.icp.photometric = false;
  const Odometry depth_only = AlignWithKeyframes(seq, options, Quiet());
  EXPECT_EQ(depth_only.pairs[0].degenerate, 3);
  // Its information says so: the wall's distance (the optical axis) known far better than the
  // prior's 5 mm, the slide along it (x) not (MeasuredInformation).
  const Eigen::Matrix<double, 6, 6> covariance = depth_only.pairs[0].information.inverse();
  EXPECT_LT(std::sqrt(covariance(5, 5)), 0.1 * options.icp.prior_sigma);
  EXPECT_GT(std::sqrt(covariance(3, 3)), 0.9 * options.icp.prior_sigma);
  // The fourth pair's prior came from three such pairs in a row: the slide's uncertainty has
  // grown to (1 + 3 g) sigma (g = prior_sigma_growth), the distance's has not.
  ASSERT_EQ(depth_only.pairs[3].degenerate, 3);
  EXPECT_EQ(PriorAge(depth_only.pairs, 3), 3);
  const double grown = (1 + 3 * options.icp.prior_sigma_growth) * options.icp.prior_sigma;
  ASSERT_GT(grown, 2 * options.icp.prior_sigma);
  const Eigen::Matrix<double, 6, 6> aged = depth_only.pairs[3].information.inverse();
  EXPECT_NEAR(std::sqrt(aged(3, 3)), grown, 0.05 * grown);  // the depth and the prior said nothing else
  EXPECT_LT(std::sqrt(aged(5, 5)), 0.1 * options.icp.prior_sigma);
  const Rigid3d truth = poses[0].inverse() * poses[1];
  const Rigid3d& first = depth_only.t0.world_from_camera[1];
  EXPECT_GT((first.translation() - truth.translation()).norm(), 0.01);
  EXPECT_GT(AngleDeg(first.linear().transpose() * truth.linear()), 0.3);
}

// A run that stopped at frame 4 and one over all 8 frames that continues from its cache must
// give exactly the poses of an uncached run over all 8.
TEST(AlignWithKeyframes, ACachedPrefixContinuesToTheSamePoses) {
  const Poses poses = Turn(8, 2.5, 0.02);
  const RgbdSequence all = WriteAndRead("keyframes_cache", SyntheticScene(), poses);
  OdometryOptions options;
  options.keyframes.max_rotation_deg = 6;  // keyframes at about every third frame
  const Odometry fresh = AlignWithKeyframes(all, options, Quiet());
  OdometryRun run = Quiet();
  run.cache_file = testing::FreshTempDir("keyframes_cache_out") / "pairs.json";
  const Odometry prefix = AlignWithKeyframes(Reread(all, 4), options, run);
  EXPECT_EQ(prefix.timings.pairs_cached, 0);
  const Odometry resumed = AlignWithKeyframes(all, options, run);
  EXPECT_EQ(resumed.timings.pairs_cached, 4);
  EXPECT_EQ(resumed.timings.pairs_computed, 3);
  EXPECT_LT(resumed.timings.frames_processed, 8);  // from the prefix's last keyframe on
  const Odometry again = AlignWithKeyframes(all, options, run);
  EXPECT_EQ(again.timings.pairs_cached, 7);
  EXPECT_EQ(again.timings.frames_processed, 0);
  for (size_t i = 0; i < fresh.t0.size(); ++i) {
    EXPECT_EQ(fresh.t0.world_from_camera[i].matrix(), resumed.t0.world_from_camera[i].matrix()) << i;
    EXPECT_EQ(fresh.t0.world_from_camera[i].matrix(), again.t0.world_from_camera[i].matrix()) << i;
  }
  EXPECT_GT(fresh.timings.keyframes, 2);
  options.keyframes.max_rotation_deg = 7;  // another option: nothing comes from the cache
  EXPECT_EQ(AlignWithKeyframes(all, options, run).timings.pairs_cached, 0);
}

TEST(AlignWithKeyframes, TheSamePosesForAnyThreadCountAndEachDepthImageOnce) {
  const Poses poses = Turn(7, 2.0, 0.02);
  const RgbdSequence seq = WriteAndRead("keyframes_threads", SyntheticScene(), poses);
  std::mutex mutex;
  std::map<int, int> calls;
  OdometryRun run = Quiet();
  run.on_depth = [&](int frame, const cv::Mat&) {
    std::lock_guard<std::mutex> lock(mutex);
    ++calls[frame];
  };
  Odometry one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = AlignWithKeyframes(seq, OdometryOptions(), run);
  }
  ASSERT_EQ(calls.size(), 7u);
  for (const auto& [frame, count] : calls) EXPECT_EQ(count, 1) << frame;
  const Odometry many = AlignWithKeyframes(seq, OdometryOptions(), Quiet());
  for (size_t i = 0; i < one.t0.size(); ++i) {
    EXPECT_EQ(one.t0.world_from_camera[i].matrix(), many.t0.world_from_camera[i].matrix()) << i;
  }
}

TEST(AlignFrames, KeyframesOffIsTheConsecutiveChain) {
  const Poses poses = Turn(4, 1.5, 0.03);
  const RgbdSequence seq = WriteAndRead("keyframes_off", SyntheticScene(), poses);
  OdometryOptions options;
  options.keyframes.enabled = false;
  const Odometry odometry = AlignFrames(seq, options, Quiet());
  EXPECT_EQ(odometry.timings.sift_frames, 4);
  EXPECT_TRUE(OdometryKeyframes(odometry).empty());
  for (const PairAlignment& pair : odometry.pairs) {
    EXPECT_EQ(pair.method, AlignmentMethod::kSift);
    EXPECT_EQ(pair.reference, pair.frame - 1);
  }
  ExpectKeyframesMatchTruth(odometry, poses, 0.01, 0.3);
}

}  // namespace
}  // namespace f2c
