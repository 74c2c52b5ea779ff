#include "f2c/refine/local_alignment.h"

#include <gtest/gtest.h>

#include <map>

namespace f2c {
namespace {

PairAlignment Pair(int frame, AlignmentMethod method, int inliers, double fitness, double x) {
  PairAlignment p;
  p.frame = frame;
  p.method = method;
  p.inliers = inliers;
  p.fitness = fitness;
  if (method == AlignmentMethod::kIcp) p.degenerate = 3;  // a plain wall's: two slides and a turn left free
  p.prev_from_curr.translation() = Eigen::Vector3d(x, 0, 0);
  p.prev_from_curr.linear() = Eigen::AngleAxisd(0.01 * frame, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

TEST(PairConfidence, SiftIcpPriorAndFitness) {
  const LocalAlignmentOptions o;
  // The authors' sigmoid: 5 inliers give 1/2, many give ~1.
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kSift, 5, 1.0, 0), o), 0.5, 1e-12);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kSift, 100, 1.0, 0), o), 1.0, 1e-9);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0), o), 0.3, 1e-12);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kMotionPrior, 0, 0.0, 0), o), 0.01, 1e-12);
  // Fitness 0.5 is a quarter of the way from 0.4 to 0.8; below 0.4 the floor of 0.05.
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kSift, 100, 0.5, 0), o), 0.25, 1e-9);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kIcp, 0, 0.1, 0), o), 0.3 * 0.05, 1e-12);
  // An ICP pair whose every direction the depth or the image measured counts like a SIFT
  // pair; one that left directions to the prediction stays at 0.3.
  PairAlignment measured = Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0);
  measured.degenerate = 0;
  EXPECT_NEAR(PairConfidence(measured, o), 1.0, 1e-12);
  EXPECT_NEAR(PairConfidence(Pair(1, AlignmentMethod::kIcp, 0, 1.0, 0), o), 0.3, 1e-12);
  measured.fitness = 0.5;
  EXPECT_NEAR(PairConfidence(measured, o), 0.25, 1e-12);
  LocalAlignmentOptions half;
  half.icp_measured_weight = 0.5;
  EXPECT_NEAR(PairConfidence(measured, half), 0.125, 1e-12);
}

TEST(LocalConstraints, PowersOfTwoChainedWithTheWeakestLink) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k < 20; ++k) pairs.push_back(Pair(k, AlignmentMethod::kSift, 100, 1.0, 0.1 * k));
  pairs[9] = Pair(10, AlignmentMethod::kIcp, 0, 1.0, 1.0);  // frames 9 -> 10
  LocalAlignmentOptions o;
  o.max_power = 4;  // the paper's spans
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  // j + 1, 2, 4, 8, 16 inside 20 frames: 19 + 18 + 16 + 12 + 4.
  ASSERT_EQ(c.size(), 69u);
  for (const RelativePoseConstraint& r : c) {
    Rigid3d chained = Rigid3d::Identity();
    for (int k = r.frame_a + 1; k <= r.frame_b; ++k) chained = chained * pairs[k - 1].prev_from_curr;
    EXPECT_LT((r.translation_a_from_b - chained.translation()).norm(), 1e-12);
    EXPECT_LT(r.rotation_a_from_b.angularDistance(Eigen::Quaterniond(chained.linear())), 1e-12);
    const bool spans_icp = r.frame_a < 10 && r.frame_b >= 10;
    EXPECT_NEAR(r.weight, spans_icp ? 0.3 : PairConfidence(pairs[0], o), 1e-9) << r.frame_a << " " << r.frame_b;
    // The ICP pair left three directions to the prediction: every span across it is unmeasured.
    EXPECT_EQ(r.measured, !spans_icp) << r.frame_a << " " << r.frame_b;
  }
}

// Keyframe odometry: frames 1-3 aligned to keyframe 0, frame 3 starting a keyframe, frames 4
// and 5 aligned to 3, frame 2's alignment weak. Relative poses come from T0 along the tree of
// references; weights are the weakest alignment on the tree path. Frame 5's own alignment
// (span 2 from frame 3) is one of the spans; frame 3's (span 3) is added as its own.
TEST(LocalConstraints, KeyframeReferencesFollowTheTreeOfReferences) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k <= 5; ++k) {
    PairAlignment p = Pair(k, AlignmentMethod::kTrack, 100, 1.0, 0.1 * k);
    p.reference = k <= 3 ? 0 : 3;
    p.keyframe = k == 3;
    pairs.push_back(p);
  }
  pairs[1] = Pair(2, AlignmentMethod::kIcp, 0, 1.0, 0.2);
  pairs[1].reference = 0;
  std::vector<Rigid3d> world(6, Rigid3d::Identity());
  for (int k = 1; k <= 5; ++k) world[k] = world[pairs[k - 1].reference] * pairs[k - 1].prev_from_curr;
  LocalAlignmentOptions o;
  o.max_power = 1;  // spans 1 and 2
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  const double strong = PairConfidence(pairs[0], o), weak = 0.3;
  std::map<std::pair<int, int>, double> expected = {
      {{0, 1}, strong}, {{1, 2}, weak},   {{2, 3}, weak},   {{3, 4}, strong}, {{4, 5}, strong},
      {{0, 2}, weak},   {{1, 3}, strong}, {{2, 4}, weak},   {{3, 5}, strong}, {{0, 3}, strong}};
  ASSERT_EQ(c.size(), expected.size());
  for (const RelativePoseConstraint& r : c) {
    const auto it = expected.find({r.frame_a, r.frame_b});
    ASSERT_NE(it, expected.end()) << r.frame_a << " " << r.frame_b;
    EXPECT_NEAR(r.weight, it->second, 1e-9) << r.frame_a << " " << r.frame_b;
    const Rigid3d a_from_b = world[r.frame_a].inverse() * world[r.frame_b];
    EXPECT_LT((r.translation_a_from_b - a_from_b.translation()).norm(), 1e-12);
    EXPECT_LT(r.rotation_a_from_b.angularDistance(Eigen::Quaterniond(a_from_b.linear())), 1e-12);
  }
}

// A constraint is measured when every pair on its path in the tree of references measured
// every direction: SIFT, tracking and ICP with nothing left to the prediction are; ICP that
// left directions to it (degenerate > 0) and the motion prior itself are not.
TEST(LocalConstraints, MeasuredWhereEveryPairOnThePathMeasuredEveryDirection) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k <= 6; ++k) pairs.push_back(Pair(k, AlignmentMethod::kTrack, 100, 1.0, 0.1 * k));
  pairs[1] = Pair(2, AlignmentMethod::kIcp, 0, 1.0, 0.2);  // frames 1 -> 2, degenerate 3
  pairs[3] = Pair(4, AlignmentMethod::kIcp, 0, 1.0, 0.4);  // frames 3 -> 4, every direction measured
  pairs[3].degenerate = 0;
  pairs[5] = Pair(6, AlignmentMethod::kMotionPrior, 0, 0.0, 0.6);  // frames 5 -> 6
  LocalAlignmentOptions o;
  o.max_power = 1;
  std::map<std::pair<int, int>, bool> expected = {
      {{0, 1}, true}, {{1, 2}, false}, {{2, 3}, true}, {{3, 4}, true}, {{4, 5}, true}, {{5, 6}, false},
      {{0, 2}, false}, {{1, 3}, false}, {{2, 4}, true}, {{3, 5}, true}, {{4, 6}, false}};
  pairs[2].inliers = 30;  // frames 2 -> 3, tracked with few keypoints
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  ASSERT_EQ(c.size(), expected.size());
  for (const RelativePoseConstraint& r : c) {
    const auto it = expected.find({r.frame_a, r.frame_b});
    ASSERT_NE(it, expected.end()) << r.frame_a << " " << r.frame_b;
    EXPECT_EQ(r.measured, it->second) << r.frame_a << " " << r.frame_b;
    // The weakest SIFT or tracked pair on the path; ICP and the prior count as none.
    const bool through_3 = r.frame_a < 3 && r.frame_b >= 3;
    const bool tracked = !(r.frame_a == 1 && r.frame_b == 2) && !(r.frame_a == 3 && r.frame_b == 4) &&
                         !(r.frame_a == 5 && r.frame_b == 6);
    EXPECT_EQ(r.weakest_inliers, through_3 ? 30 : tracked ? 100 : kNoInlierCount) << r.frame_a << " " << r.frame_b;
  }
}

TEST(LocalConstraints, DistanceWeightingOfTheAuthors) {
  std::vector<PairAlignment> pairs = {Pair(1, AlignmentMethod::kSift, 100, 1.0, 0.25)};
  LocalAlignmentOptions o;
  o.distance_sigma = 0.25;
  const std::vector<RelativePoseConstraint> c = LocalConstraints(pairs, o);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_NEAR(c[0].weight, PairConfidence(pairs[0], o) * std::exp(-0.5), 1e-9);
}

}  // namespace
}  // namespace f2c
