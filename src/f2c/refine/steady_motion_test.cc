#include "f2c/refine/steady_motion.h"

#include <gtest/gtest.h>

#include "f2c/util/error.h"

namespace f2c {
namespace {

// Every triple of consecutive frames, each increment scaled to a velocity per 1/30 s; triples
// across a gap longer than max_gap medians, or a time stamp that does not advance, are left
// out. Frames at 30 Hz, one dropped (frame 3 two intervals after frame 2), a pause after 4.
TEST(SteadyMotionConstraints, ScalesByTheIntervalsAndBreaksAtGaps) {
  std::vector<double> t = {0, 1, 2, 4, 5, 20, 21, 22, 22};
  for (double& s : t) s /= 30;
  const std::vector<SteadyMotionConstraint> c = SteadyMotionConstraints(t, {});
  ASSERT_EQ(c.size(), 4u);
  const int frames[4][3] = {{0, 1, 2}, {1, 2, 3}, {2, 3, 4}, {5, 6, 7}};
  const double scales[4][2] = {{1, 1}, {1, 0.5}, {0.5, 1}, {1, 1}};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(c[i].frame_a, frames[i][0]);
    EXPECT_EQ(c[i].frame_b, frames[i][1]);
    EXPECT_EQ(c[i].frame_c, frames[i][2]);
    EXPECT_NEAR(c[i].scale_ab, scales[i][0], 1e-12);
    EXPECT_NEAR(c[i].scale_bc, scales[i][1], 1e-12);
  }
  // A wider gap admits the 15-interval jump (scale 1/15) and the triples around it.
  SteadyMotionOptions wide;
  wide.max_gap = 20;
  const std::vector<SteadyMotionConstraint> w = SteadyMotionConstraints(t, wide);
  ASSERT_EQ(w.size(), 6u);
  EXPECT_NEAR(w[3].scale_bc, 1.0 / 15, 1e-12);
  EXPECT_TRUE(SteadyMotionConstraints({0, 1}, {}).empty());
  // At 15 Hz every increment counts half.
  const std::vector<SteadyMotionConstraint> slow = SteadyMotionConstraints({0, 1.0 / 15, 2.0 / 15}, {});
  ASSERT_EQ(slow.size(), 1u);
  EXPECT_DOUBLE_EQ(slow[0].scale_ab, 0.5);
  EXPECT_DOUBLE_EQ(slow[0].scale_bc, 0.5);
}

// A triple that contains a pair the odometry left to the motion prior weighs
// unmeasured_weight and is not `measured`; the others weigh 1 and are.
TEST(SteadyMotionConstraints, WeighsTriplesOverPairsLeftToThePrior) {
  const std::vector<double> t = {0, 1, 2, 3, 4, 5};
  const std::vector<char> unmeasured = {0, 0, 0, 1, 0, 0};  // frame 3's pair
  SteadyMotionOptions o;
  o.unmeasured_weight = 3;
  const std::vector<SteadyMotionConstraint> c = SteadyMotionConstraints(t, o, unmeasured);
  ASSERT_EQ(c.size(), 4u);
  const double expected[4] = {1, 3, 3, 1};  // centred on frames 1, 2, 3, 4
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(c[i].weight, expected[i]) << i;
    EXPECT_EQ(c[i].measured, expected[i] == 1) << i;
  }
  for (const SteadyMotionConstraint& v : SteadyMotionConstraints(t, o)) {
    EXPECT_EQ(v.weight, 1);
    EXPECT_TRUE(v.measured);
  }
  EXPECT_THROW(SteadyMotionConstraints(t, o, {0, 1}), std::logic_error);
}

TEST(SteadyMotionConstraints, RejectsAGapBelowOneInterval) {
  SteadyMotionOptions o;
  o.max_gap = 0.5;
  EXPECT_THROW(o.Check(), InputError);
}

}  // namespace
}  // namespace f2c
