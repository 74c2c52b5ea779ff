#include "f2c/refine/self_check.h"

#include <gtest/gtest.h>

#include <set>

#include "f2c/refine/correspondences.h"

namespace f2c {
namespace {

const CameraIntrinsics kCamera{525.0, 525.0, 319.5, 239.5, 640, 480};

// Two frames 10 cm apart along x that see the same wall z = 2 (a 1 m square sampled every
// 5 cm), frame b's copy of it moved by `shift_b` (its own coordinates).
FeatureIndex TwoViewsOfAWall(const Eigen::Vector3f& shift_b) {
  FeatureIndex index;
  for (int frame = 0; frame < 2; ++frame) {
    FrameFeatures f;
    const Eigen::Vector3f offset =
        frame == 0 ? Eigen::Vector3f(Eigen::Vector3f::Zero()) : Eigen::Vector3f(Eigen::Vector3f(-0.1f, 0, 0) + shift_b);
    for (int i = 0; i < 20; ++i) {
      for (int j = 0; j < 20; ++j) {
        Feature x;
        x.type = FeatureType::kPlane;
        x.position = Eigen::Vector3f(-0.5f + 0.05f * i, -0.5f + 0.05f * j, 2) + offset;
        x.direction = Eigen::Vector3f(0, 0, -1);
        x.salience = 1;
        f.features.push_back(x);
      }
    }
    index.frames.push_back(BuildFrameIndex(f, FeatureIndexOptions{}));
  }
  return index;
}

PoseVector TruePoses() {
  PoseVector poses(2);
  poses[1].translation = Eigen::Vector3d(0.1, 0, 0);
  return poses;
}

TEST(HeldOut, OneInEveryByAHashTheSameEachTime) {
  int held = 0;
  for (int frame = 0; frame < 100; ++frame) {
    for (int feature = 0; feature < 1000; ++feature) held += HeldOut(frame, feature, 10);
  }
  EXPECT_NEAR(held / 100000.0, 0.1, 0.005);
  EXPECT_EQ(HeldOut(3, 7, 10), HeldOut(3, 7, 10));
  EXPECT_FALSE(HeldOut(3, 7, 0));  // 0: none
}

// S vanishes where the frames agree, is the square of the offset where one frame's surface
// stands off the other's by less than tau, and saturates at tau beyond it.
TEST(ScoreHeldOut, MeanSquaredTruncatedPointToPlaneDisagreement) {
  SelfCheckOptions o;
  o.every = 2;
  const std::vector<FramePair> pairs = {{0, 1, 1.0f}};
  // At most points_per_pair (8) held-out features of each side of a pair.
  EXPECT_EQ(ScoreHeldOut(pairs, TwoViewsOfAWall(Eigen::Vector3f::Zero()), TruePoses(), kCamera, o, 5.0).points, 16);
  o.points_per_pair = 1000;
  const SelfCheckScore exact =
      ScoreHeldOut(pairs, TwoViewsOfAWall(Eigen::Vector3f::Zero()), TruePoses(), kCamera, o, 5.0);
  EXPECT_GT(exact.points, 150);
  EXPECT_LT(exact.Rms(), 1e-6);
  EXPECT_EQ(exact.agreeing, exact.points);
  // Frame b's wall 1 cm nearer: every held-out feature 1 cm off the other frame's plane.
  const SelfCheckScore off = ScoreHeldOut(pairs, TwoViewsOfAWall({0, 0, -0.01f}), TruePoses(), kCamera, o, 5.0);
  EXPECT_NEAR(off.Rms(), 0.01, 1e-5);
  // 8 cm: beyond tau (3 cm), each counts tau.
  const SelfCheckScore far = ScoreHeldOut(pairs, TwoViewsOfAWall({0, 0, -0.08f}), TruePoses(), kCamera, o, 5.0);
  EXPECT_NEAR(far.Rms(), o.tau, 1e-6);
  EXPECT_EQ(far.agreeing, 0);
  // Seen by neither camera (frame b turned away): nothing measured.
  PoseVector away = TruePoses();
  away[1].rotation = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY());
  const SelfCheckScore none = ScoreHeldOut(pairs, TwoViewsOfAWall(Eigen::Vector3f::Zero()), away, kCamera, o, 5.0);
  EXPECT_EQ(none.points, 0);
  EXPECT_EQ(none.score, 0);
}

TEST(UnitePairs, SortedEachOnce) {
  const std::vector<FramePair> u = UnitePairs({{2, 3, 0.5f}, {0, 1, 0.5f}}, {{0, 1, 0.7f}, {1, 4, 0.2f}});
  ASSERT_EQ(u.size(), 3u);
  EXPECT_EQ(std::pair(u[0].a, u[0].b), std::pair(0, 1));
  EXPECT_EQ(std::pair(u[1].a, u[1].b), std::pair(1, 4));
  EXPECT_EQ(std::pair(u[2].a, u[2].b), std::pair(2, 3));
}

// The kept pairs come back for the kept poses alone; other poses are searched.
TEST(CheckPairCache, ReusesThePairsOfTheSamePosesOnly) {
  const FeatureIndex index = TwoViewsOfAWall(Eigen::Vector3f::Zero());
  const PairOptions options;
  const std::vector<FramePair> searched = WholeScanPairs(index, TruePoses(), kCamera, options);
  ASSERT_EQ(searched.size(), 1u);  // the two views overlap
  CheckPairCache cache;
  cache.Keep(TruePoses(), {{0, 1, 0.5f}, {0, 1, 0.25f}});  // marked: not what a search gives
  EXPECT_EQ(cache.For(index, TruePoses(), kCamera, options).size(), 2u);
  PoseVector moved = TruePoses();
  moved[1].translation.y() += 1e-9;
  const std::vector<FramePair> fresh = cache.For(index, moved, kCamera, options);
  ASSERT_EQ(fresh.size(), 1u);
  EXPECT_EQ(std::pair(fresh[0].a, fresh[0].b), std::pair(0, 1));
}

// The shares of pairs scored under the kept poses are taken as kept; a pair not scored, or
// other poses, are scored.
TEST(CheckPairCache, ReusesTheSharesOfTheSamePosesOnly) {
  const FeatureIndex index = TwoViewsOfAWall({0, 0, -0.01f});
  const SelfCheckOptions o;
  const std::vector<FramePair> pairs = {{0, 1, 1.0f}};
  const std::vector<PairShare> scored = SharesOfPairs(pairs, index, TruePoses(), kCamera, o, 5.0);
  ASSERT_EQ(scored.size(), 1u);
  ASSERT_GT(scored[0].points, 0);
  ASSERT_GT(scored[0].sum, 0);
  EXPECT_EQ(SumShares(scored, 1).score, ScoreHeldOut(pairs, index, TruePoses(), kCamera, o, 5.0).score);
  CheckPairCache cache;
  PairShare marked;  // not what scoring gives
  marked.sum = 7;
  marked.points = 3;
  cache.Keep(TruePoses(), pairs, pairs, {marked});
  const std::vector<PairShare> reused = cache.Shares(pairs, index, TruePoses(), kCamera, o, 5.0);
  ASSERT_EQ(reused.size(), 1u);
  EXPECT_EQ(reused[0].sum, 7);
  EXPECT_EQ(reused[0].points, 3);
  PoseVector moved = TruePoses();
  moved[1].translation.y() += 1e-9;
  const std::vector<PairShare> rescored = cache.Shares(pairs, index, moved, kCamera, o, 5.0);
  ASSERT_EQ(rescored.size(), 1u);
  EXPECT_EQ(rescored[0].points, scored[0].points);
  EXPECT_NEAR(rescored[0].sum, scored[0].sum, 1e-9);
  // A pair the cache did not score is scored, beside the kept one.
  cache.Keep(TruePoses(), pairs, {{0, 2, 1.0f}}, {marked});
  const std::vector<PairShare> unknown = cache.Shares(pairs, index, TruePoses(), kCamera, o, 5.0);
  EXPECT_EQ(unknown[0].sum, scored[0].sum);
  EXPECT_EQ(unknown[0].points, scored[0].points);
}

// E_C never sees a held-out feature: it is neither a correspondence's point nor its target.
TEST(FindCorrespondences, LeavesHeldOutFeaturesAlone) {
  const FeatureIndex index = TwoViewsOfAWall(Eigen::Vector3f::Zero());
  WindowOptions windows;
  windows.polish_iterations = 0;
  const WindowSchedule schedule(windows, {0.0, 0.1});
  CorrespondenceOptions o;
  o.per_frame = 400;  // every feature tried
  o.attempts = 10;
  o.held_out_every = 4;
  std::set<std::tuple<int, float, float, float>> held;
  for (int frame = 0; frame < 2; ++frame) {
    const FeatureCloud& planes = index.frames[frame]->family(FeatureFamily::kPlane);
    for (int i = 0; i < planes.size(); ++i) {
      if (HeldOut(frame, i, o.held_out_every))
        held.insert({frame, planes.point(i).x(), planes.point(i).y(), planes.point(i).z()});
    }
  }
  ASSERT_GT(held.size(), 100u);
  const std::vector<FeatureCorrespondence> c =
      FindCorrespondences({{0, 1, 1.0f}}, index, TruePoses(), schedule, 0, {0.0, 0.1}, o);
  EXPECT_GT(c.size(), 400u);
  for (const FeatureCorrespondence& x : c) {
    EXPECT_EQ(held.count({x.point_frame, x.point.x(), x.point.y(), x.point.z()}), 0u);
    EXPECT_EQ(held.count({x.target_frame, x.target_point.x(), x.target_point.y(), x.target_point.z()}), 0u);
  }
}

}  // namespace
}  // namespace f2c
