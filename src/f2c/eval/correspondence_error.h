#pragma once
// The authors' benchmark metric (paper §5): for each ground-truth correspondence between
// frames a and b, the distance between the point mapped to the world by each frame's
// estimated pose, |T_a p_a - T_b p_b|; reported as RMSE (and the other statistics) in
// metres. It needs no ground-truth trajectory, only point pairs, and it is insensitive to
// the global frame of the estimate: it measures exactly what a bent or doubled wall costs.

#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "f2c/eval/trajectory_error.h"
#include "f2c/io/correspondences.h"

namespace f2c {

// The estimate's pose at each frame time (nearest estimate stamp within
// max_time_difference, one-to-one as the TUM tools associate), or none.
std::vector<std::optional<Rigid3d>> PosesAtFrames(const Trajectory& estimate,
                                                  const std::vector<double>& frame_timestamps,
                                                  double max_time_difference);

// The paper's Fig. 9: errors grouped by frame gap in powers of two: bin k holds gaps in [2^k, 2^(k+1)). Empty bins
// are left out; the median of an even count is the mean of the middle two.
struct GapBin {
  int gap_lo = 0, gap_hi = 0;  // [lo, hi)
  int count = 0;
  double mean = 0, median = 0;
};
std::vector<GapBin> BinByGap(const std::vector<std::pair<int, double>>& gap_errors);

struct CorrespondenceResult {
  ErrorStatistics distance;    // metres, over the correspondences whose frames both have poses
  std::vector<GapBin> by_gap;  // the same distances by frame gap |a - b| (the paper's Fig. 9)
  int skipped = 0;             // correspondences with a frame that has no estimated pose
};

// The correspondences between two frames that a frame selection keeps (IoOptions: frames
// first..last of the sequence, last < 0 the end, then every N-th), renumbered as the selected
// sequence numbers its frames (original first + j every is j); the others are left out. So
// `evaluate --last 2000` measures a prefix against a whole scan's correspondences.
std::vector<Correspondence> SelectFrames(const std::vector<Correspondence>& correspondences, int first, int last,
                                         int every);

// The result as `evaluate --json` prints it under "correspondences" (distance_m, by_frame_gap,
// skipped), for the CLI and the Python module alike.
nlohmann::json ToJson(const CorrespondenceResult& result);

// InputError naming `source` when a correspondence refers to a frame beyond `poses`.
CorrespondenceResult CorrespondenceError(const std::vector<std::optional<Rigid3d>>& world_from_frame,
                                         const std::vector<Correspondence>& correspondences, const std::string& source);

}  // namespace f2c
