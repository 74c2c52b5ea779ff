#pragma once
// Candidate frame pairs of one iteration (paper §4.2: correspondences are searched "for every
// pair of scans in every window"; DESIGN.md §3: pairs from overlap, cost linear in frames).
//
// A pair (a, b), a < b, is a candidate when
//   - a and b share a window in this iteration (refine/windows.h);
//   - their views can overlap under the current poses: the optical axes are within
//     max_view_angle, and at least min_overlap of one frame's coverage points (a spread
//     subsample of its features) project into the other camera's image within max_depth.
// Testing every pair that shares a window would cost O(n l_i), quadratic once a window holds
// the scan. Instead frames are binned by the world position of their features' centroid on a
// grid of cell_size; for frame a and each power-of-two index gap [2^k, 2^(k+1)) only
// per_octave frames of each neighbouring cell are tested, evenly spread over the gap, and the
// per_octave best-overlapping are kept. So each frame has O(log l_i) partners, near ones and
// far ones alike (loop closures), and an iteration costs O(n log n).

#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/optim/pose.h"
#include "f2c/refine/feature_index.h"
#include "f2c/refine/windows.h"
#include "f2c/util/fields.h"

namespace f2c {

struct PairOptions {
  double cell_size = 1.0;          // metres
  double min_overlap = 0.2;        // fraction of coverage points
  double max_view_angle_deg = 90;  // between optical axes
  double max_depth = 5.0;          // metres: beyond it a camera is taken not to see a point
  int per_octave = 2;
  // Pairs at least long_range_gap frames apart join only frames whose index is a multiple of
  // long_range_stride (1: all frames): the long-range links that close loops then tie fewer
  // poses together, and the Cholesky factor fills in less on long scans.
  int long_range_stride = 1;
  int long_range_gap = 32;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: frame pairs and correspondences (paper 4.2)");
    F2C_FIELD(v, cell_size, "--pair-cell-size", Positive(),
              "grid of frames' feature centroids for pair candidates (m)");
    F2C_FIELD(v, min_overlap, "--min-overlap", Between(0, 1),
              "pairs: share of one frame's points the other camera sees");
    F2C_FIELD(v, max_view_angle_deg, "--max-view-angle", AboveUpTo(0, 180),
              "pairs: largest angle between optical axes (deg)");
    F2C_FIELD(v, max_depth, "", Positive(), "beyond this a camera is taken not to see a point (m)");
    F2C_FIELD(v, per_octave, "--pairs-per-octave", AtLeast(1), "partners per frame and power-of-two frame gap");
    F2C_FIELD(v, long_range_stride, "--long-range-stride", AtLeast(1),
              "pairs far apart join only every N-th frame (1: all)");
    F2C_FIELD(v, long_range_gap, "--long-range-gap", AtLeast(1), "...when at least this many frames apart");
  }
  void Check() const;
};

struct FramePair {
  int32_t a = 0;
  int32_t b = 0;  // a < b
  float overlap = 0;
};

// Pairs sorted by (a, b).
std::vector<FramePair> CandidatePairs(const WindowSchedule& schedule, int iteration, const FeatureIndex& index,
                                      const PoseVector& poses, const CameraIntrinsics& intrinsics,
                                      const PairOptions& options);

// Fraction of frame a's coverage points that camera b sees (in its image, 0 < z <= max_depth),
// with b_from_a the relative pose.
float CoverageSeen(const FrameIndex& a, const Eigen::Isometry3f& b_from_a, const CameraIntrinsics& intrinsics,
                   double max_depth);

}  // namespace f2c
