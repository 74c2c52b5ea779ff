#include "f2c/refine/correspondences.h"

#include <cmath>

#include <gtest/gtest.h>

namespace f2c {
namespace {

TEST(Thresholds, AgeDecaysLinearlyToTheFinalValues) {
  const CorrespondenceOptions o;  // 0.5 m / 45 deg -> 0.15 m / 20 deg over 3 iterations
  const double deg = M_PI / 180;
  EXPECT_NEAR(ThresholdsForAge(o, 0).max_distance, 0.5, 1e-12);
  EXPECT_NEAR(ThresholdsForAge(o, 0).max_angle, 45 * deg, 1e-12);
  EXPECT_NEAR(ThresholdsForAge(o, 1).max_distance, 0.5 - 0.35 / 3, 1e-12);
  EXPECT_NEAR(ThresholdsForAge(o, 2).max_angle, (45 - 2 * 25.0 / 3) * deg, 1e-12);
  EXPECT_NEAR(ThresholdsForAge(o, 3).max_distance, 0.15, 1e-12);
  EXPECT_NEAR(ThresholdsForAge(o, 9).max_angle, 20 * deg, 1e-12);
}

TEST(Thresholds, AuthorsPerPairPathVariant) {
  const CorrespondenceOptions o;
  // min + sqrt(d / (L / 2)) (max - min): d = L/8 gives half way; d >= L/2 the maximum.
  EXPECT_NEAR(ThresholdsForPath(o, 0.0, 6.0).max_distance, 0.15, 1e-12);
  EXPECT_NEAR(ThresholdsForPath(o, 0.75, 6.0).max_distance, 0.325, 1e-12);
  EXPECT_NEAR(ThresholdsForPath(o, 0.75, 6.0).max_angle, 32.5 * M_PI / 180, 1e-12);
  EXPECT_NEAR(ThresholdsForPath(o, 5.0, 6.0).max_distance, 0.5, 1e-12);
}

Feature MakeFeature(FeatureType type, Eigen::Vector3f position, Eigen::Vector3f direction) {
  Feature f;
  f.type = type;
  f.position = position;
  f.direction = direction.normalized();
  f.salience = 1;
  return f;
}

WindowOptions NoPolish() {
  WindowOptions o;
  o.extra_iterations = 4;
  o.polish_iterations = 0;
  return o;
}

// Two frames 10 cm apart along x looking at the same things: a wall z = 2 sampled on a grid,
// a plane facing the other way, and a vertical edge.
struct TwoFrames {
  FeatureIndex index;
  PoseVector poses;
  WindowSchedule schedule{NoPolish(), {0.0, 0.1}};
};

TwoFrames MakeTwoFrames(const Eigen::Vector3f& shift_b) {
  TwoFrames t;
  t.poses.resize(2);
  t.poses[1].translation = Eigen::Vector3d(0.1, 0, 0);
  for (int frame = 0; frame < 2; ++frame) {
    FrameFeatures f;
    const Eigen::Vector3f offset =
        frame == 0 ? Eigen::Vector3f(Eigen::Vector3f::Zero()) : Eigen::Vector3f(Eigen::Vector3f(-0.1f, 0, 0) + shift_b);
    for (int i = 0; i < 10; ++i) {
      for (int j = 0; j < 10; ++j) {
        f.features.push_back(MakeFeature(FeatureType::kPlane,
                                         Eigen::Vector3f(-0.5f + 0.1f * i, -0.5f + 0.1f * j, 2) + offset, {0, 0, -1}));
      }
    }
    for (int i = 0; i < 10; ++i) {
      f.features.push_back(MakeFeature(FeatureType::kSilhouette, Eigen::Vector3f(0.7f, -0.5f + 0.1f * i, 1.5f) + offset,
                                       {0, frame == 0 ? 1.0f : -1.0f, 0}));  // sign of an edge's direction is arbitrary
    }
    t.index.frames.push_back(BuildFrameIndex(f, FeatureIndexOptions{}));
  }
  return t;
}

TEST(FindCorrespondences, ClosestCompatibleFeaturesWithinThresholds) {
  const TwoFrames t = MakeTwoFrames(Eigen::Vector3f::Zero());
  CorrespondenceOptions o;
  o.per_frame = 20;  // 40 for the one pair
  CorrespondenceStats stats;
  const std::vector<FeatureCorrespondence> c =
      FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o, &stats);
  EXPECT_EQ(stats.per_pair, 40);
  EXPECT_EQ(static_cast<int>(c.size()), 40);
  EXPECT_EQ(stats.total(), 40);
  int from_each[2] = {0, 0};
  for (const FeatureCorrespondence& x : c) {
    ++from_each[x.point_frame];
    // The frames agree exactly: every match is the same world point.
    const Eigen::Vector3d target = t.poses[x.target_frame].ToRigid() * x.target_point.cast<double>();
    const Eigen::Vector3d point = t.poses[x.point_frame].ToRigid() * x.point.cast<double>();
    EXPECT_LT((target - point).norm(), 1e-6);
    EXPECT_EQ(x.kind == CorrespondenceKind::kPointToLine, x.feature_type == static_cast<int>(FeatureType::kSilhouette));
    EXPECT_FLOAT_EQ(x.weight, x.kind == CorrespondenceKind::kPointToLine ? 0.6f : 1.0f);
  }
  EXPECT_EQ(from_each[0], 20);  // half of the share from each side
  EXPECT_EQ(from_each[1], 20);
  // Deterministic; another seed samples other features.
  EXPECT_EQ(FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o).front().point,
            c.front().point);
  o.seed = 5;
  const std::vector<FeatureCorrespondence> other =
      FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o);
  int same = 0;
  for (size_t i = 0; i < other.size(); ++i) same += other[i].point == c[i].point;
  EXPECT_LT(same, 10);
}

TEST(FindCorrespondences, NothingBeyondTheDistanceOrAngle) {
  CorrespondenceOptions o;
  // Frame b's copy moved 0.6 m off the wall: beyond the first iteration's 0.5 m.
  TwoFrames t = MakeTwoFrames(Eigen::Vector3f(0, 0, 0.6f));
  EXPECT_TRUE(FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o).empty());
  // 0.3 m: matched in the first iteration (age 0), not once the thresholds have shrunk.
  t = MakeTwoFrames(Eigen::Vector3f(0, 0, 0.3f));
  EXPECT_FALSE(FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o).empty());
  EXPECT_TRUE(FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 3, {0.0, 0.1}, o).empty());
  // A 50 degree turn of frame b: no normal agrees within 45 degrees.
  t = MakeTwoFrames(Eigen::Vector3f::Zero());
  t.poses[1].rotation = Eigen::AngleAxisd(50 * M_PI / 180, Eigen::Vector3d::UnitY());
  t.poses[1].translation = Eigen::Vector3d::Zero();
  for (const FeatureCorrespondence& x :
       FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o)) {
    EXPECT_EQ(x.kind, CorrespondenceKind::kPointToLine);  // only the vertical edge survives
  }
}

TEST(FindCorrespondences, BudgetIsSpreadOverPairsWithAFloor) {
  TwoFrames t = MakeTwoFrames(Eigen::Vector3f::Zero());
  CorrespondenceOptions o;
  o.per_frame = 3;     // 6 for 2 frames over 1 pair...
  o.min_per_pair = 8;  // ...raised to the floor
  CorrespondenceStats stats;
  const auto c = FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, t.schedule, 0, {0.0, 0.1}, o, &stats);
  EXPECT_EQ(stats.per_pair, 8);
  EXPECT_EQ(c.size(), 8u);
}

TEST(FindCorrespondences, PolishIterationsDrawTheirOwnBudget) {
  TwoFrames t = MakeTwoFrames(Eigen::Vector3f::Zero());
  WindowOptions w = NoPolish();
  w.polish_iterations = 2;
  const WindowSchedule schedule{w, {0.0, 0.1}};
  const int last = schedule.iterations() - 1;
  ASSERT_TRUE(schedule.Polishing(last));
  ASSERT_FALSE(schedule.Polishing(0));
  CorrespondenceOptions o;
  o.per_frame = 5;          // 10 for 2 frames over 1 pair
  o.polish_per_frame = 15;  // 30 in the polish iterations
  o.min_per_pair = 1;
  auto per_pair = [&](int iteration) {
    CorrespondenceStats stats;
    FindCorrespondences({{0, 1, 1.0f}}, t.index, t.poses, schedule, iteration, {0.0, 0.1}, o, &stats);
    return stats.per_pair;
  };
  EXPECT_EQ(per_pair(0), 10);
  EXPECT_EQ(per_pair(last), 30);
  o.polish_per_frame = 0;  // as the other iterations
  EXPECT_EQ(per_pair(last), 10);
}

}  // namespace
}  // namespace f2c
