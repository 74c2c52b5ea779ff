#pragma once
// The refinement's check of its own work, without ground truth (beyond the paper; issue
// "scenes it has never seen"): a share of every frame's plane features is held out of the
// energy (E_C never takes one as a correspondence's moved point), and after each iteration
// they measure how well the poses make overlapping frames agree.
//
// The measure, for a set of frame pairs P and the held-out features h of each frame:
//
//   S = 1/N sum_{(a,b) in P} sum_{h in a, then in b} min(d(h)^2, tau^2)
//
// (at most points_per_pair of each frame's held-out features per pair) with d(h) the
// distance of h, moved into the other frame by the current poses, from the
// plane of the nearest plane feature there whose normal agrees within max_angle (among the
// `neighbours` nearest within search_radius); a held-out feature that lands in the other
// camera's view (in its image, max_depth deep) but finds no such plane counts tau^2, one
// that lands outside it does not count. S is a mean squared point-to-plane disagreement,
// truncated at tau so that occlusions and the scene's own gaps weigh no more than a
// disagreement of tau. N counts the features that landed in view.
//
// An iteration is compared on one pair set: the pairs that overlap under the poses before it
// or after it, searched as in one window holding the scan (refine/pairs.h), so that loops
// count as much as neighbours. The search under the poses before it is the one after the
// last iteration, kept (CheckPairCache). An iteration whose S after is above (1 + tolerance) S before
// is not taken: the poses go back to where the iteration started, and the next iteration
// (larger windows, other correspondences) starts from there. At the end the same comparison
// between the initial and the final poses (run_tolerance): a run that leaves the frames
// agreeing less than they did at its start gives back its initial poses.

#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/optim/pose.h"
#include "f2c/refine/feature_index.h"
#include "f2c/refine/pairs.h"
#include "f2c/util/fields.h"

namespace f2c {

struct SelfCheckOptions {
  bool enabled = true;
  // One plane feature in `every` is held out (chosen by a hash of frame and feature, so the
  // same ones each iteration).
  int every = 10;
  double tau = 0.03;           // metres: the truncation
  double search_radius = 0.1;  // metres: the nearest features considered
  double max_angle_deg = 30;   // normals that agree
  int neighbours = 4;
  // Held-out features measured per pair and side, at most (from a point of the frame's list
  // chosen by the pair, onwards): the score's cost is linear in them, and a scan's thousands
  // of pairs give it hundreds of thousands of points without all of each frame's.
  int points_per_pair = 8;
  double tolerance = 0.01;  // S may grow by this share before an iteration is undone
  // ...and over the whole run (initial poses against final), before the initial poses are
  // given back: each iteration may add up to `tolerance`.
  double run_tolerance = 0.01;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: self-check");
    F2C_FIELD(v, enabled, "--self-check,!--no-self-check", {},
              "hold out plane features and undo an iteration that makes overlapping frames agree less");
    F2C_FIELD(v, every, "--self-check-every", AtLeast(2), "one plane feature in this many is held out");
    F2C_FIELD(v, tau, "--self-check-tau", Positive(), "truncation of the held-out point-to-plane distances (m)");
    F2C_FIELD(v, search_radius, "", Positive(), "held-out features' search radius (m)");
    F2C_FIELD(v, max_angle_deg, "", AboveUpTo(0, 180), "held-out features' normal agreement (deg)");
    F2C_FIELD(v, neighbours, "", Between(1, 64), "nearest features checked per held-out feature");
    F2C_FIELD(v, points_per_pair, "", AtLeast(1), "held-out features measured per pair and side, at most");
    F2C_FIELD(v, tolerance, "--self-check-tolerance", AtLeast(0),
              "an iteration is undone when it raises the check's score by more than this share");
    F2C_FIELD(v, run_tolerance, "--self-check-run-tolerance", AtLeast(0),
              "the initial poses are kept when the whole run raises the check's score by more than this share");
  }
  void Check() const;
};

// Whether plane feature `feature` of frame `frame` is held out (every >= 2; 0: none is).
bool HeldOut(int frame, int feature, int every);

struct SelfCheckScore {
  double score = 0;      // S (m^2)
  int64_t points = 0;    // N
  int64_t agreeing = 0;  // of those, the ones within tau
  int pairs = 0;
  double Rms() const;  // sqrt(S), metres
};

// One pair's share of S: its measured features' truncated squares, their count, and how many
// of them agree within tau.
struct PairShare {
  double sum = 0;
  int64_t points = 0, agreeing = 0;
};

// Each pair's share of S under `poses`; where `skip` is given, the pairs it marks are left
// at zero.
std::vector<PairShare> SharesOfPairs(const std::vector<FramePair>& pairs, const FeatureIndex& index,
                                     const PoseVector& poses, const CameraIntrinsics& intrinsics,
                                     const SelfCheckOptions& options, double max_depth,
                                     const std::vector<char>* skip = nullptr);
// S from the shares of `pairs` pairs, summed in their order.
SelfCheckScore SumShares(const std::vector<PairShare>& shares, int pairs);

// S of `poses` over `pairs` (refine/pairs.h's, any window).
SelfCheckScore ScoreHeldOut(const std::vector<FramePair>& pairs, const FeatureIndex& index, const PoseVector& poses,
                            const CameraIntrinsics& intrinsics, const SelfCheckOptions& options, double max_depth);

// The pairs that overlap under `poses` as if one window held the scan (refine/pairs.h).
std::vector<FramePair> WholeScanPairs(const FeatureIndex& index, const PoseVector& poses,
                                      const CameraIntrinsics& intrinsics, const PairOptions& options);
// Both lists' pairs, sorted by (a, b), each once.
std::vector<FramePair> UnitePairs(std::vector<FramePair> a, const std::vector<FramePair>& b);

// What the check knows of the poses an iteration starts from, kept from the end of the last
// one: the whole-scan pairs under them and the shares of S of the pairs it scored under them.
// The poses are the same unless something moved them in between (the loops' presolve). An
// iteration's check scores each pair before and after; the shares before are the last
// iteration's shares after, so only the pairs new to it are scored again (half the check's
// cost), and each pair's share is the same number either way.
struct CheckPairCache {
  PoseVector poses;
  std::vector<FramePair> pairs;
  std::vector<FramePair> scored;  // sorted by (a, b), each once
  std::vector<PairShare> shares;  // of `scored`, under `poses`
  // The pairs under `poses`, searched only when they are not the kept poses.
  std::vector<FramePair> For(const FeatureIndex& index, const PoseVector& poses, const CameraIntrinsics& intrinsics,
                             const PairOptions& options) const;
  // The shares of `check` (sorted by (a, b), each once) under `query`: the kept ones where
  // `query` are the kept poses, the others scored.
  std::vector<PairShare> Shares(const std::vector<FramePair>& check, const FeatureIndex& index, const PoseVector& query,
                                const CameraIntrinsics& intrinsics, const SelfCheckOptions& options,
                                double max_depth) const;
  void Keep(const PoseVector& kept_poses, std::vector<FramePair> kept_pairs, std::vector<FramePair> kept_scored = {},
            std::vector<PairShare> kept_shares = {});
};

// One iteration's check.
struct SelfCheckRecord {
  bool done = false;  // the check ran
  SelfCheckScore before, after;
  bool undone = false;  // the iteration was not taken
};

nlohmann::json ToJson(const SelfCheckRecord& record);

}  // namespace f2c
