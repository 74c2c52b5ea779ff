#include "f2c/refine/pairs.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "f2c/util/error.h"

namespace f2c {

void PairOptions::Check() const { CheckFields(*this); }

float CoverageSeen(const FrameIndex& a, const Eigen::Isometry3f& b_from_a, const CameraIntrinsics& k,
                   double max_depth) {
  if (a.coverage.empty()) return 0;
  int seen = 0;
  for (const Eigen::Vector3f& p : a.coverage) {
    const Eigen::Vector3f q = b_from_a * p;
    if (!(q.z() > 0.05f && q.z() <= max_depth)) continue;
    const double u = k.fx * q.x() / q.z() + k.cx;
    const double v = k.fy * q.y() / q.z() + k.cy;
    seen += u >= -0.5 && v >= -0.5 && u < k.width - 0.5 && v < k.height - 0.5;
  }
  return static_cast<float>(seen) / static_cast<float>(a.coverage.size());
}

namespace {

struct CellKey {
  int32_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  size_t operator()(const CellKey& c) const {
    return (static_cast<size_t>(c.x) * 73856093u) ^ (static_cast<size_t>(c.y) * 19349663u) ^
           (static_cast<size_t>(c.z) * 83492791u);
  }
};

}  // namespace

std::vector<FramePair> CandidatePairs(const WindowSchedule& schedule, int iteration, const FeatureIndex& index,
                                      const PoseVector& poses, const CameraIntrinsics& intrinsics,
                                      const PairOptions& options) {
  options.Check();
  const int n = static_cast<int>(poses.size());
  F2C_CHECK(static_cast<int>(index.frames.size()) == n && schedule.frames() == n, "one pose and index per frame");
  std::vector<Eigen::Isometry3f> world_from_camera(n);
  std::vector<CellKey> cell(n);
  std::unordered_map<CellKey, std::vector<int>, CellHash> grid;
  for (int k = 0; k < n; ++k) {
    world_from_camera[k] = poses[k].ToRigid().cast<float>();
    if (index.frames[k]->empty()) continue;
    const Eigen::Vector3f c = world_from_camera[k] * index.frames[k]->centroid / static_cast<float>(options.cell_size);
    cell[k] = {static_cast<int32_t>(std::floor(c.x())), static_cast<int32_t>(std::floor(c.y())),
               static_cast<int32_t>(std::floor(c.z()))};
    grid[cell[k]].push_back(k);  // frame order: each cell's list is sorted
  }
  const float min_axis_cos = static_cast<float>(std::cos(options.max_view_angle_deg * M_PI / 180.0));

  std::vector<std::vector<FramePair>> per_frame(n);
  tbb::parallel_for(0, n, [&](int a) {
    if (index.frames[a]->empty()) return;
    const int end = schedule.ShareEnd(iteration, a);
    std::vector<FramePair> tested;
    for (int64_t lo = 1; a + lo < end; lo *= 2) {
      const bool long_range = lo >= options.long_range_gap && options.long_range_stride > 1;
      if (long_range && a % options.long_range_stride != 0) break;
      const int gap_begin = a + static_cast<int>(lo);
      const int gap_end = static_cast<int>(std::min<int64_t>(a + 2 * lo, end));
      tested.clear();
      for (int dx = -1; dx <= 1; ++dx) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find({cell[a].x + dx, cell[a].y + dy, cell[a].z + dz});
            if (it == grid.end()) continue;
            const std::vector<int>& frames = it->second;
            const auto first = std::lower_bound(frames.begin(), frames.end(), gap_begin);
            const auto last = std::lower_bound(first, frames.end(), gap_end);
            const int64_t count = last - first;
            const int take = static_cast<int>(std::min<int64_t>(count, options.per_octave));
            for (int j = 0; j < take; ++j) {
              auto at = first + (2 * j + 1) * count / (2 * take);  // evenly spread over the gap
              if (long_range) {
                // The nearest anchor frame of the cell at or after it (else before it).
                auto anchor = at;
                while (anchor != last && *anchor % options.long_range_stride != 0) ++anchor;
                if (anchor == last) {
                  anchor = at;
                  while (anchor != first && *anchor % options.long_range_stride != 0) --anchor;
                  if (*anchor % options.long_range_stride != 0) continue;
                }
                at = anchor;
              }
              const int b = *at;
              const Eigen::Vector3f axis_a = world_from_camera[a].linear().col(2);
              const Eigen::Vector3f axis_b = world_from_camera[b].linear().col(2);
              if (axis_a.dot(axis_b) < min_axis_cos) continue;
              const Eigen::Isometry3f b_from_a = world_from_camera[b].inverse() * world_from_camera[a];
              const float overlap =
                  std::max(CoverageSeen(*index.frames[a], b_from_a, intrinsics, options.max_depth),
                           CoverageSeen(*index.frames[b], b_from_a.inverse(), intrinsics, options.max_depth));
              if (overlap >= options.min_overlap && overlap > 0) tested.push_back({a, b, overlap});
            }
          }
        }
      }
      std::sort(tested.begin(), tested.end(), [](const FramePair& x, const FramePair& y) {
        return x.overlap != y.overlap ? x.overlap > y.overlap : x.b < y.b;
      });
      if (static_cast<int>(tested.size()) > options.per_octave) tested.resize(options.per_octave);
      per_frame[a].insert(per_frame[a].end(), tested.begin(), tested.end());
    }
    std::sort(per_frame[a].begin(), per_frame[a].end(),
              [](const FramePair& x, const FramePair& y) { return x.b < y.b; });
  });
  std::vector<FramePair> pairs;
  for (const auto& p : per_frame) pairs.insert(pairs.end(), p.begin(), p.end());
  return pairs;
}

}  // namespace f2c
