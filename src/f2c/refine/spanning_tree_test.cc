#include "f2c/refine/spanning_tree.h"

#include <gtest/gtest.h>

namespace f2c {
namespace {

Rigid3d Step(double yaw_deg, double x) {
  Rigid3d t = Rigid3d::Identity();
  t.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, 0, 0);
  return t;
}

PoseVector Chain(const std::vector<Rigid3d>& steps) {
  PoseVector poses(1);
  for (const Rigid3d& s : steps) poses.push_back(Pose::FromRigid(poses.back().ToRigid() * s));
  return poses;
}

double Distance(const Pose& a, const Pose& b) {
  return (a.translation - b.translation).norm() + a.rotation.angularDistance(b.rotation);
}

TEST(SpanningTreePoses, WithoutLoopsNothingMoves) {
  const PoseVector poses = Chain({Step(5, 0.1), Step(-3, 0.2), Step(1, 0.1)});
  const PoseVector out = SpanningTreePoses(poses, {1.0, 0.3, 1.0}, {});
  for (size_t k = 0; k < poses.size(); ++k) EXPECT_LT(Distance(out[k], poses[k]), 1e-12);
}

// Frames 0-1-2-3-4, the true steps 10 cm straight ahead; the odometry got link 2-3 wrong by
// 40 degrees. A loop 1 -> 4 (weighted 0.95, the link 0.3) re-places 3 and 4 by the loop:
// both land on the truth, and frames before the loop stay.
TEST(SpanningTreePoses, AWeakLinkOnALoopGivesWay) {
  const PoseVector truth = Chain({Step(0, 0.1), Step(0, 0.1), Step(0, 0.1), Step(0, 0.1)});
  const PoseVector odometry = Chain({Step(0, 0.1), Step(0, 0.1), Step(40, 0.1), Step(0, 0.1)});
  LoopEdge loop;
  loop.frame_a = 1;
  loop.frame_b = 4;
  loop.a_from_b = truth[1].ToRigid().inverse() * truth[4].ToRigid();
  const PoseVector out = SpanningTreePoses(odometry, {1.0, 1.0, 0.3, 1.0}, {loop});
  for (int k = 0; k < 5; ++k) {
    if (k == 3) continue;  // placed from 4 through link 3-4, which keeps its own relative pose
    EXPECT_LT(Distance(out[k], truth[k]), 1e-9) << k;
  }
  EXPECT_LT(Distance(out[3], Pose::FromRigid(out[4].ToRigid() * Step(0, 0.1).inverse())), 1e-9);
  // With a trusted link (1.0 > 0.95) the loop is left out of the tree.
  const PoseVector kept = SpanningTreePoses(odometry, {1.0, 1.0, 1.0, 1.0}, {loop});
  for (int k = 0; k < 5; ++k) EXPECT_LT(Distance(kept[k], odometry[k]), 1e-9) << k;
}

// Keyframe odometry links each frame to its reference: frames 1 and 2 both hang off frame 0,
// link 0-1 weak (frame 1 turned 20 degrees too far), link 0-2 trusted. A loop 1 -> 2 then
// re-places frame 1 from frame 2. Read as consecutive links (0-1 weak, 1-2 trusted) the loop
// would close a cycle through the trusted link and frame 1 would stay wrong.
TEST(SpanningTreePoses, LinksJoinEachFrameToItsReference) {
  const Rigid3d truth_1 = Step(0, 0.1);
  const PoseVector odometry = {Pose::FromRigid(Rigid3d::Identity()), Pose::FromRigid(Step(20, 0.1)),
                               Pose::FromRigid(Step(0, 0.2))};
  LoopEdge loop;
  loop.frame_a = 1;
  loop.frame_b = 2;
  loop.a_from_b = truth_1.inverse() * odometry[2].ToRigid();
  const PoseVector out = SpanningTreePoses(odometry, {0.3, 1.0}, {loop}, {0, 0});
  EXPECT_LT(Distance(out[1], Pose::FromRigid(truth_1)), 1e-9);
  EXPECT_LT(Distance(out[2], odometry[2]), 1e-12);
  const PoseVector consecutive = SpanningTreePoses(odometry, {0.3, 1.0}, {loop});
  EXPECT_LT(Distance(consecutive[1], odometry[1]), 1e-12);
}

// Loops the poses agree with need no placing: edges measured 1-2 cm or 0.5 deg off the
// poses (RANSAC noise) give a median of about that, whatever one wrong edge says; a loop the
// poses have not closed (every new edge 0.3 m off) gives 0.3 m. Only the newest edges count.
TEST(LoopDisagreement, TheMedianOfTheNewestEdges) {
  const PoseVector poses = Chain({Step(5, 0.1), Step(-3, 0.2), Step(1, 0.1), Step(2, 0.3), Step(0, 0.2)});
  auto edge = [&](int a, int b, const Rigid3d& error) {
    LoopEdge e;
    e.frame_a = a;
    e.frame_b = b;
    e.a_from_b = poses[a].ToRigid().inverse() * poses[b].ToRigid() * error;
    return e;
  };
  std::vector<LoopEdge> loops = {edge(0, 3, Step(0.5, 0.01)), edge(0, 4, Step(0, 0.02)), edge(1, 4, Step(-0.5, 0.015)),
                                 edge(1, 5, Step(40, 0.5))};  // one wrong edge
  // Per edge 0.01 (the translation beats 0.5 deg at 1 m, 0.0087), 0.02, 0.015, 0.698: the
  // (upper) median is 0.02.
  EXPECT_NEAR(LoopDisagreement(poses, loops, 4, 1.0), 0.02, 1e-9);
  EXPECT_NEAR(LoopDisagreement(poses, loops, 100, 1.0), 0.02, 1e-9);           // more than there are: all
  EXPECT_NEAR(LoopDisagreement(poses, loops, 1, 1.0), 40 * M_PI / 180, 1e-9);  // the newest alone
  EXPECT_EQ(LoopDisagreement(poses, loops, 0, 1.0), 0.0);
  // The rotation counts at the lever arm: 0.5 deg at 3 m is 2.6 cm.
  EXPECT_NEAR(LoopDisagreement(poses, {loops[0]}, 1, 3.0), 3.0 * 0.5 * M_PI / 180, 1e-9);
  // A loop not closed yet: three new edges 0.3 m off, after the agreeing ones.
  for (int a : {0, 1, 2}) loops.push_back(edge(a, 5, Step(0, 0.3)));
  EXPECT_NEAR(LoopDisagreement(poses, loops, 3, 1.0), 0.3, 1e-9);
}

}  // namespace
}  // namespace f2c
