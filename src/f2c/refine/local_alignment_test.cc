#include "f2c/refine/local_alignment.h"

#include <gtest/gtest.h>

namespace f2c {
namespace {

PairAlignment Pair(int frame, AlignmentMethod method, int inliers, double fitness, double x) {
  PairAlignment p;
  p.frame = frame;
  p.method = method;
  p.inliers = inliers;
  p.fitness = fitness;
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
}

TEST(LocalConstraints, PowersOfTwoChainedWithTheWeakestLink) {
  std::vector<PairAlignment> pairs;
  for (int k = 1; k < 20; ++k) pairs.push_back(Pair(k, AlignmentMethod::kSift, 100, 1.0, 0.1 * k));
  pairs[9] = Pair(10, AlignmentMethod::kIcp, 0, 1.0, 1.0);  // frames 9 -> 10
  LocalAlignmentOptions o;
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
