#include "f2c/refine/pairs.h"

#include <gtest/gtest.h>

#include <set>

namespace f2c {
namespace {

const CameraIntrinsics kIntrinsics{525.0, 525.0, 319.5, 239.5, 640, 480};

// Frames 10 cm apart along x, all looking at a wall 2 m ahead (+z), except `away`, turned
// to face the other way.
struct Row {
  FeatureIndex index;
  PoseVector poses;
};

Row MakeRow(int n, int away) {
  Row row;
  for (int k = 0; k < n; ++k) {
    Pose pose;
    pose.translation = Eigen::Vector3d(0.1 * k, 0, 0);
    if (k == away) pose.rotation = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY());
    row.poses.push_back(pose);
    FrameFeatures f;
    for (int i = 0; i < 8; ++i) {
      for (int j = 0; j < 6; ++j) {
        Feature x;
        x.position = Eigen::Vector3f(-0.8f + 0.2f * i, -0.5f + 0.2f * j, 2.0f);  // in its camera
        x.direction = Eigen::Vector3f(0, 0, -1);
        f.features.push_back(x);
      }
    }
    row.index.frames.push_back(BuildFrameIndex(f, FeatureIndexOptions{}));
  }
  return row;
}

WindowSchedule Schedule(int n) {
  WindowOptions o;
  o.initial_frames = 4;
  o.extra_iterations = 0;
  o.polish_iterations = 0;
  std::vector<double> path(n);
  for (int k = 0; k < n; ++k) path[k] = 0.1 * k;
  return WindowSchedule(o, path);
}

TEST(CandidatePairs, FramesThatShareAWindowAndSeeTheSameWall) {
  const Row row = MakeRow(12, 5);
  const WindowSchedule schedule = Schedule(12);
  const std::vector<FramePair> pairs = CandidatePairs(schedule, 0, row.index, row.poses, kIntrinsics, PairOptions{});
  std::set<std::pair<int, int>> got, want;
  for (const FramePair& p : pairs) {
    got.insert({p.a, p.b});
    EXPECT_LT(p.a, p.b);
    EXPECT_GT(p.overlap, 0.5f);
  }
  // Windows of 4 overlapping by 2: every pair within one, but none with frame 5.
  for (int a = 0; a < 12; ++a) {
    for (int b = a + 1; b < 12; ++b) {
      if (a != 5 && b != 5 && schedule.Share(0, a, b)) want.insert({a, b});
    }
  }
  EXPECT_EQ(got, want);
  // Sorted by (a, b).
  for (size_t i = 1; i < pairs.size(); ++i) {
    EXPECT_TRUE(pairs[i - 1].a < pairs[i].a || (pairs[i - 1].a == pairs[i].a && pairs[i - 1].b < pairs[i].b));
  }
}

TEST(CandidatePairs, AtMostPerOctavePartnersPerPowerOfTwoGap) {
  const int n = 64;
  const Row row = MakeRow(n, -1);
  const WindowSchedule schedule = Schedule(n);
  const int last = schedule.iterations() - 1;  // one window holds all 64
  PairOptions o;
  o.per_octave = 1;
  o.cell_size = 10.0;  // every frame in one cell
  const std::vector<FramePair> pairs = CandidatePairs(schedule, last, row.index, row.poses, kIntrinsics, o);
  std::map<std::pair<int, int>, int> per_octave;
  for (const FramePair& p : pairs) ++per_octave[{p.a, static_cast<int>(std::log2(p.b - p.a))}];
  for (const auto& [key, count] : per_octave) EXPECT_EQ(count, 1) << key.first << " octave " << key.second;
  // Frame 0 gets a partner in each octave up to gap 32..63 whose views overlap (frames up to
  // about 1.6 m along still see part of the wall).
  EXPECT_GE(per_octave.count({0, 0}) + per_octave.count({0, 1}) + per_octave.count({0, 2}) + per_octave.count({0, 3}),
            4u);
  // About n log n pairs, not n^2 / 2.
  EXPECT_LT(pairs.size(), static_cast<size_t>(n * 7));
}

// --long-range-stride: pairs at least long_range_gap frames apart join only frames whose
// index is a multiple of the stride; nearer pairs are as before.
TEST(CandidatePairs, LongRangePairsJoinOnlyEveryStrideThFrame) {
  const int n = 32;
  const Row row = MakeRow(n, -1);
  const WindowSchedule schedule = Schedule(n);
  const int last = schedule.iterations() - 1;
  PairOptions o;
  o.cell_size = 10.0;
  o.long_range_gap = 8;
  const std::vector<FramePair> all = CandidatePairs(schedule, last, row.index, row.poses, kIntrinsics, o);
  o.long_range_stride = 4;
  const std::vector<FramePair> strided = CandidatePairs(schedule, last, row.index, row.poses, kIntrinsics, o);
  int long_pairs = 0, short_from_other_frames = 0;
  for (const FramePair& p : strided) {
    if (p.b - p.a >= 8) {
      ++long_pairs;
      EXPECT_EQ(p.a % 4, 0) << p.a << "-" << p.b;
      EXPECT_EQ(p.b % 4, 0) << p.a << "-" << p.b;
    } else {
      short_from_other_frames += p.a % 4 != 0;
    }
  }
  EXPECT_GT(long_pairs, 0);
  EXPECT_GT(short_from_other_frames, 0);
  int all_long = 0;
  for (const FramePair& p : all) all_long += p.b - p.a >= 8;
  EXPECT_LT(long_pairs, all_long);
}

TEST(CoverageSeen, FractionInsideTheOtherImage) {
  FrameFeatures f;
  for (const Eigen::Vector3f& p : {Eigen::Vector3f(0, 0, 2), Eigen::Vector3f(0.5f, 0, 2), Eigen::Vector3f(3, 0, 2)}) {
    Feature x;
    x.position = p;
    x.direction = Eigen::Vector3f(0, 0, -1);
    f.features.push_back(x);
  }
  const auto frame = BuildFrameIndex(f, FeatureIndexOptions{});
  EXPECT_FLOAT_EQ(CoverageSeen(*frame, Eigen::Isometry3f::Identity(), kIntrinsics, 5.0), 2.0f / 3.0f);
  // Beyond the depth range: unseen.
  EXPECT_FLOAT_EQ(CoverageSeen(*frame, Eigen::Isometry3f::Identity(), kIntrinsics, 1.5), 0.0f);
}

}  // namespace
}  // namespace f2c
