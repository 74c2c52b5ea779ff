#include "f2c/eval/correspondence_error.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

// Three frames looking at world points; correspondences made from the true poses.
struct Fixture {
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> truth;
  std::vector<Correspondence> correspondences;
  Fixture() {
    for (int i = 0; i < 3; ++i) {
      Rigid3d pose = Rigid3d::Identity();
      pose.linear() = Eigen::AngleAxisd(0.2 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
      pose.translation() = Eigen::Vector3d(0.5 * i, 0.1, -1.0);
      truth.push_back(pose);
    }
    const Eigen::Vector3d world[4] = {{0, 0, 2}, {1, 0.5, 3}, {-0.5, -0.2, 2.5}, {0.3, 0.3, 1.5}};
    for (const auto& [a, b] : {std::pair{0, 1}, {0, 2}, {1, 2}}) {
      for (const Eigen::Vector3d& p : world) {
        correspondences.push_back({a, b, truth[a].inverse() * p, truth[b].inverse() * p});
      }
    }
  }
};

TEST(CorrespondenceError, VanishesAtTheTruthAndUnderAnyGlobalMotion) {
  const Fixture f;
  std::vector<std::optional<Rigid3d>> poses(f.truth.begin(), f.truth.end());
  EXPECT_NEAR(CorrespondenceError(poses, f.correspondences, "x").distance.rmse, 0.0, 1e-12);
  // The metric ignores the estimate's world frame.
  Rigid3d g = Rigid3d::Identity();
  g.linear() = Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  g.translation() = Eigen::Vector3d(4, -2, 7);
  for (auto& p : poses) p = g * *p;
  const CorrespondenceResult r = CorrespondenceError(poses, f.correspondences, "x");
  EXPECT_NEAR(r.distance.rmse, 0.0, 1e-9);
  EXPECT_EQ(r.distance.count, 12);
}

TEST(CorrespondenceError, MeasuresTheDisplacementOfAWrongPose) {
  const Fixture f;
  std::vector<std::optional<Rigid3d>> poses(f.truth.begin(), f.truth.end());
  poses[2]->translation() += Eigen::Vector3d(0, 0.03, 0.04);  // frame 2 off by 5 cm
  const CorrespondenceResult r = CorrespondenceError(poses, f.correspondences, "x");
  // 8 of the 12 correspondences involve frame 2, each off by exactly 5 cm.
  EXPECT_EQ(r.distance.count, 12);
  EXPECT_NEAR(r.distance.max, 0.05, 1e-12);
  EXPECT_NEAR(r.distance.rmse, std::sqrt(8 * 0.05 * 0.05 / 12), 1e-12);
  EXPECT_NEAR(r.distance.median, 0.05, 1e-12);
  // By frame gap (Fig. 9): gap 1 (pairs 0-1 and 1-2: 4 of 8 off), gap 2 (pair 0-2: all off).
  ASSERT_EQ(r.by_gap.size(), 2u);
  EXPECT_EQ(r.by_gap[0].gap_lo, 1);
  EXPECT_EQ(r.by_gap[0].count, 8);
  EXPECT_NEAR(r.by_gap[0].mean, 0.025, 1e-12);
  EXPECT_NEAR(r.by_gap[0].median, 0.025, 1e-12);  // even count: (0 + 0.05) / 2
  EXPECT_EQ(r.by_gap[1].gap_lo, 2);
  EXPECT_NEAR(r.by_gap[1].median, 0.05, 1e-12);
}

TEST(CorrespondenceError, FramesWithoutPosesAreSkippedAndUnknownFramesAreErrors) {
  Fixture f;
  std::vector<std::optional<Rigid3d>> poses(f.truth.begin(), f.truth.end());
  poses[1].reset();
  const CorrespondenceResult r = CorrespondenceError(poses, f.correspondences, "x");
  EXPECT_EQ(r.skipped, 8);
  EXPECT_EQ(r.distance.count, 4);
  Correspondence beyond;
  beyond.frame_b = 7;
  f.correspondences.push_back(beyond);
  EXPECT_EQ(testing::InputErrorMessage([&] { CorrespondenceError(poses, f.correspondences, "c.txt"); }),
            "c.txt: a correspondence refers to frame 7 but the dataset has 3 frames");
}

TEST(SelectFrames, KeepsPairsInsideTheSelectionRenumbered) {
  auto pair = [](int a, int b) {
    Correspondence c;
    c.frame_a = a, c.frame_b = b;
    c.point_in_a = Eigen::Vector3d(a, b, 1);
    return c;
  };
  const std::vector<Correspondence> all = {pair(0, 4), pair(2, 6), pair(3, 5), pair(4, 10), pair(6, 12), pair(8, 9)};
  // Frames 2..10, every 2nd: 2, 4, 6, 8, 10 become 0..4; odd frames, 0 and 12 are not selected.
  const std::vector<Correspondence> kept = SelectFrames(all, 2, 10, 2);
  ASSERT_EQ(kept.size(), 2u);
  EXPECT_EQ(kept[0].frame_a, 0);
  EXPECT_EQ(kept[0].frame_b, 2);
  EXPECT_EQ(kept[0].point_in_a, Eigen::Vector3d(2, 6, 1));  // the points travel with their pair
  EXPECT_EQ(kept[1].frame_a, 1);
  EXPECT_EQ(kept[1].frame_b, 4);
  // A prefix (--last 5): pairs reaching beyond it are left out, not errors.
  const std::vector<Correspondence> prefix = SelectFrames(all, 0, 5, 1);
  ASSERT_EQ(prefix.size(), 2u);
  EXPECT_EQ(prefix[0].frame_b, 4);
  EXPECT_EQ(prefix[1].frame_a, 3);
  EXPECT_EQ(SelectFrames(all, 0, -1, 1).size(), all.size());  // no selection: all of them
}

TEST(PosesAtFrames, AssociatesByTimeStamp) {
  Trajectory estimate;
  Rigid3d p = Rigid3d::Identity();
  for (int i = 0; i < 3; ++i) {
    p.translation().x() = i;
    estimate.Add(10.0 + 0.1 * i + 0.005, p);  // 5 ms off the frame times
  }
  const auto poses = PosesAtFrames(estimate, {10.0, 10.1, 10.2, 10.3}, 0.02);
  ASSERT_EQ(poses.size(), 4u);
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(poses[i].has_value());
    EXPECT_EQ(poses[i]->translation().x(), i);
  }
  EXPECT_FALSE(poses[3].has_value());
}

TEST(BinByGap, PowersOfTwoWithEvenAndOddMedians) {
  // Gaps 1 | 2, 3 | 4..7 | 8..15: errors chosen so that each median is easy to check.
  const std::vector<std::pair<int, double>> e = {{1, 0.1}, {1, 0.3}, {2, 0.5}, {3, 0.2}, {3, 0.9},
                                                 {4, 1.0}, {7, 3.0}, {5, 2.0}, {6, 8.0}, {9, 4.0}};
  const std::vector<GapBin> b = BinByGap(e);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(b[0].gap_lo, 1);
  EXPECT_EQ(b[0].gap_hi, 2);
  EXPECT_DOUBLE_EQ(b[0].median, 0.2);  // even: (0.1 + 0.3) / 2
  EXPECT_EQ(b[1].count, 3);
  EXPECT_DOUBLE_EQ(b[1].median, 0.5);  // odd: 0.2, 0.5, 0.9
  EXPECT_NEAR(b[1].mean, 1.6 / 3, 1e-12);
  EXPECT_DOUBLE_EQ(b[2].median, 2.5);  // 1, 2, 3, 8
  EXPECT_EQ(b[3].gap_lo, 8);
  EXPECT_DOUBLE_EQ(b[3].median, 4.0);
  EXPECT_TRUE(BinByGap({}).empty());
}

}  // namespace
}  // namespace f2c
