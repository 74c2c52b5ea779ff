#pragma once
// Beyond the paper (issue: "SIFT re-matching of the frame pairs that come to share a window"):
// the closest-feature correspondences of E_C only find a loop once the drift inside a window
// is smaller than their thresholds, and nothing local can remove drift where the odometry
// had no evidence (a plain wall: ICP slides and turns freely along it). Appearance can: when
// two keyframes first share a window, and they are a loop (farther apart than E_L reaches)
// or the odometry between them is weak, their SIFT features are matched (ratio test, RANSAC
// in 3D as the odometry does), the answer checked against their depth features, and the
// inlier points kept as E_M constraints for every later iteration.
//
// Candidates are chosen loosely from the current poses (cameras within
// max_camera_distance, optical axes within max_view_angle), since the poses may still be
// wrong by what the match is meant to fix; bridges over weak odometry are tried with no pose
// test at all. Each keyframe tries at most candidates_per_keyframe new bridges and as many
// new loops per iteration (the shortest bridges, the best-overlapping loops first). A pair is
// tried once.

#include <nlohmann/json_fwd.hpp>
#include <set>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/matching/ransac.h"
#include "f2c/odometry/odometry.h"
#include "f2c/optim/constraints.h"
#include "f2c/optim/pose.h"
#include "f2c/refine/feature_index.h"
#include "f2c/refine/keyframes.h"
#include "f2c/refine/spanning_tree.h"
#include "f2c/refine/windows.h"
#include "f2c/util/fields.h"

namespace f2c {

struct SiftLoopOptions {
  bool enabled = true;
  KeyframeOptions keyframes;
  int candidates_per_keyframe = 2;
  double max_camera_distance = 3.0;  // metres, under the current poses
  double max_view_angle_deg = 90;
  // Loops: keyframes at least loop_gap frames apart (E_L holds nearer ones).
  int loop_gap = 32;
  // Bridges: keyframes at most max_bridge_gap frames apart with an odometry pair between them
  // whose E_L confidence is below weak_confidence; tried whatever the current poses say.
  int max_bridge_gap = 96;
  double weak_confidence = 0.9;
  double ratio = 0.7;  // Lowe's ratio test
  RansacOptions ransac;
  int min_inliers = 20;
  // Depth check of a RANSAC answer: of b's plane features that camera a sees under it, at
  // least this share must lie within check_distance of the plane of a's nearest plane feature
  // (within check_radius), whose normal agrees within check_angle.
  double min_fitness = 0.3;
  double check_distance = 0.05;  // metres (depth noise at 3 m is about 2 cm, and both frames have it)
  double check_radius = 0.2;     // metres
  double check_angle_deg = 20;
  int max_points_per_pair = 30;  // inliers kept per matched pair
  // In an iteration that accepted new matches, first solve E_M + E_L + E_I to convergence
  // (refine/refine.h), so closest points are searched under the poses the loops imply.
  bool presolve = true;
  // ...when the re-placement moved a pose, or a match is off, by more than this (metres).
  double presolve_min_change = 0.1;
  // ...starting from poses re-placed along the maximum spanning tree of the odometry links
  // and the loops (refine/spanning_tree.h), loops trusted like this.
  bool spanning_tree = true;
  // ...and also solved from the current poses, keeping whichever start ends at the lower
  // E_L + E_M + E_V. The tree replaces the refined relative poses on every cycle's weakest
  // link by a loop's single RANSAC estimate; where the odometry has few weak links (the
  // photometric step measured a plain wall's slides), one imprecise loop then places a long
  // stretch, and E_M's Cauchy loss no longer sees the loops that would bring it back:
  // measured, 5,000 frames with the photometric
  // options 0.035 -> 0.0077 m ATE.
  bool better_start = true;
  double loop_confidence = 0.95;
  uint64_t seed = 0;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: SIFT loops and bridges (beyond the paper)");
    F2C_FIELD(v, enabled, "--sift-loops,!--no-sift-loops", {},
              "SIFT re-matching of keyframes (--no-sift-loops: closest features only, as the paper)");
    F2C_NESTED(v, keyframes);
    F2C_FIELD(v, candidates_per_keyframe, "--loop-candidates", AtLeast(1),
              "new loop (and bridge) partners per keyframe and iteration");
    F2C_FIELD(v, loop_gap, "--loop-gap", AtLeast(1), "loops: keyframes at least this many frames apart");
    F2C_FIELD(v, max_bridge_gap, "--bridge-gap", AtLeast(1),
              "bridges over weak odometry: at most this many frames apart");
    F2C_FIELD(v, weak_confidence, "", Between(0, 1), "bridges: odometry pairs below this E_L confidence");
    F2C_FIELD(v, max_camera_distance, "--loop-max-distance", Positive(),
              "loops: cameras at most this far apart now (m)");
    F2C_FIELD(v, max_view_angle_deg, "--loop-max-view-angle", AboveUpTo(0, 180),
              "loops: optical axes within this now (deg)");
    F2C_FIELD(v, ratio, "--loop-ratio", AboveUpTo(0, 1), "loops: SIFT ratio test");
    v.Nested(ransac, "ransac", /*flags=*/false);
    F2C_FIELD(v, min_inliers, "--loop-min-inliers", AtLeast(3), "loops: RANSAC inliers needed");
    F2C_FIELD(v, min_fitness, "--loop-min-fitness", Between(0, 1),
              "loops: share of seen planes the match must explain");
    F2C_FIELD(v, check_distance, "", Positive(), "depth check: plane distance (m)");
    F2C_FIELD(v, check_radius, "", Positive(), "depth check: nearest plane feature within (m)");
    F2C_FIELD(v, check_angle_deg, "", AboveUpTo(0, 180), "depth check: normals within (deg)");
    F2C_FIELD(v, max_points_per_pair, "--loop-points", AtLeast(1), "E_M points kept per matched pair");
    F2C_FIELD(v, presolve, "", {}, "solve E_M + E_L + E_I first in an iteration that accepted matches");
    F2C_FIELD(v, presolve_min_change, "", AtLeast(0), "...when a pose or a match is off by more (m)");
    F2C_FIELD(v, spanning_tree, "--spanning-tree,!--no-spanning-tree", {},
              "re-place poses along the most trusted links when loops arrive");
    F2C_FIELD(v, better_start, "--loop-better-start,!--no-loop-better-start", {},
              "...and from the current poses, keeping the start that ends at the lower E_L + E_M + E_V");
    F2C_FIELD(v, loop_confidence, "", Between(0, 1), "spanning tree: trust of a loop");
    F2C_FIELD(v, seed, "", {}, "seed of the loops' RANSAC");
  }
  void Check() const;
};

struct SiftLoopStats {
  int tried = 0;     // this iteration
  int accepted = 0;  // this iteration
  int pairs = 0;     // matched pairs so far
  int points = 0;    // E_M constraints so far
  double seconds = 0;
};

class SiftLoopMatcher {
 public:
  // `confidence[k-1]` is E_L's confidence of odometry pair k (frames k-1, k).
  SiftLoopMatcher(std::vector<Keyframe> keyframes, std::vector<double> confidence, const SiftLoopOptions& options);
  SiftLoopStats Update(const WindowSchedule& schedule, int iteration, const PoseVector& poses,
                       const FeatureIndex& index, const CameraIntrinsics& intrinsics);
  const std::vector<PointMatch>& matches() const { return matches_; }
  // Each accepted pair with its matched relative pose.
  const std::vector<LoopEdge>& edges() const { return edges_; }

 private:
  bool WeakBetween(int a, int b) const;  // frames a < b
  // Matches keyframes i < j; true with their E_M points appended to `out` when accepted.
  bool TryPair(int i, int j, const FeatureIndex& index, const CameraIntrinsics& intrinsics,
               std::vector<PointMatch>* out, LoopEdge* edge) const;

  std::vector<Keyframe> keyframes_;
  std::vector<int> weak_prefix_;  // weak odometry pairs among frames 1..k
  SiftLoopOptions options_;
  std::set<std::pair<int, int>> tried_;
  std::vector<PointMatch> matches_;
  std::vector<LoopEdge> edges_;
  int pairs_ = 0;
};

nlohmann::json ToJson(const SiftLoopStats& stats);

}  // namespace f2c
