#pragma once
// Re-placing poses through the most trusted links (beyond the paper). A verified loop can
// disagree with the trajectory by tens of degrees when one odometry link is wrong (ICP turning
// freely along a plain wall). Starting the optimisation from the old poses then lands in a
// wrong minimum: least squares bends every link a little, or a robust E_L breaks the chain
// where the first gradient happens to push. Instead the poses are first propagated from frame
// 0 along a maximum spanning tree of the links (Kruskal): consecutive frames joined by their
// current relative pose, weighted by the odometry's confidence (refine/local_alignment.h),
// and loop pairs joined by their matched relative pose, weighted loop_confidence. A weak
// odometry link on a cycle with loops is left out of the tree, so the loops decide where
// what follows it goes; with no weak link on a cycle the tree is the odometry chain and the
// poses do not change.

#include <vector>

#include "f2c/geometry/rigid.h"
#include "f2c/optim/pose.h"

namespace f2c {

struct LoopEdge {
  int frame_a = 0;
  int frame_b = 0;
  Rigid3d a_from_b = Rigid3d::Identity();
  double confidence = 0.95;
};

// `link_confidence[k-1]` joins frame k to frame link_from[k-1] (its odometry reference; an
// empty link_from: k-1). Returns poses with frame 0's unchanged.
PoseVector SpanningTreePoses(const PoseVector& poses, const std::vector<double>& link_confidence,
                             const std::vector<LoopEdge>& loops, const std::vector<int>& link_from = {});

// How far the poses are from the newest loops' measured relative poses, to decide whether
// the loops need placing at all: per edge, the difference of the translations or of the
// rotations at `lever` metres per radian, whichever is larger; the median over the last
// `newest` edges (metres; 0 with none). The median, because a loop that the poses have not
// closed yet disagrees in all of its edges by about the same, while a single RANSAC edge
// can be centimetres or degrees off on its own.
double LoopDisagreement(const PoseVector& poses, const std::vector<LoopEdge>& loops, int newest, double lever);

}  // namespace f2c
