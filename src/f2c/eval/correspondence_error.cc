#include "f2c/eval/correspondence_error.h"

#include <fmt/format.h>

#include "f2c/io/readers.h"
#include "f2c/util/error.h"

namespace f2c {

std::vector<std::optional<Rigid3d>> PosesAtFrames(const Trajectory& estimate,
                                                  const std::vector<double>& frame_timestamps,
                                                  double max_time_difference) {
  std::vector<std::optional<Rigid3d>> poses(frame_timestamps.size());
  for (const auto& [frame, pose] :
       internal::AssociateTimestamps(frame_timestamps, estimate.timestamps, max_time_difference)) {
    poses[frame] = estimate.world_from_camera[pose];
  }
  return poses;
}

std::vector<GapBin> BinByGap(const std::vector<std::pair<int, double>>& gap_errors) {
  std::vector<std::vector<double>> bins;
  for (const auto& [gap, error] : gap_errors) {
    if (gap < 1 || !std::isfinite(error)) continue;
    const int k = static_cast<int>(std::floor(std::log2(static_cast<double>(gap)) + 1e-12));
    if (static_cast<int>(bins.size()) <= k) bins.resize(k + 1);
    bins[k].push_back(error);
  }
  std::vector<GapBin> out;
  for (int k = 0; k < static_cast<int>(bins.size()); ++k) {
    std::vector<double>& v = bins[k];
    if (v.empty()) continue;
    std::sort(v.begin(), v.end());
    GapBin b;
    b.gap_lo = 1 << k, b.gap_hi = 1 << (k + 1), b.count = static_cast<int>(v.size());
    double sum = 0;
    for (double e : v) sum += e;
    b.mean = sum / v.size();
    const size_t m = v.size() / 2;
    b.median = v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
    out.push_back(b);
  }
  return out;
}

std::vector<Correspondence> SelectFrames(const std::vector<Correspondence>& correspondences, int first, int last,
                                         int every) {
  F2C_CHECK(first >= 0 && every >= 1, "a frame selection starts at a frame and steps forward");
  if (first == 0 && last < 0 && every == 1) return correspondences;
  auto renumber = [&](int frame, int* selected) {
    if (frame < first || (last >= 0 && frame > last) || (frame - first) % every != 0) return false;
    *selected = (frame - first) / every;
    return true;
  };
  std::vector<Correspondence> out;
  for (Correspondence c : correspondences) {
    if (renumber(c.frame_a, &c.frame_a) && renumber(c.frame_b, &c.frame_b)) out.push_back(c);
  }
  return out;
}

CorrespondenceResult CorrespondenceError(const std::vector<std::optional<Rigid3d>>& world_from_frame,
                                         const std::vector<Correspondence>& correspondences,
                                         const std::string& source) {
  CorrespondenceResult result;
  std::vector<double> distances;
  std::vector<std::pair<int, double>> by_gap;
  const int frames = static_cast<int>(world_from_frame.size());
  for (const Correspondence& c : correspondences) {
    for (int frame : {c.frame_a, c.frame_b}) {
      if (frame < 0 || frame >= frames) {
        ThrowInputError(
            source, fmt::format("a correspondence refers to frame {} but the dataset has {} frames", frame, frames));
      }
    }
    const auto& a = world_from_frame[c.frame_a];
    const auto& b = world_from_frame[c.frame_b];
    if (!a || !b) {
      ++result.skipped;
      continue;
    }
    distances.push_back((*a * c.point_in_a - *b * c.point_in_b).norm());
    by_gap.emplace_back(std::abs(c.frame_b - c.frame_a), distances.back());
  }
  result.distance = ComputeStatistics(std::move(distances));
  result.by_gap = BinByGap(by_gap);
  return result;
}

nlohmann::json ToJson(const CorrespondenceResult& r) {
  nlohmann::json by_gap = nlohmann::json::array();
  for (const GapBin& b : r.by_gap) {
    by_gap.push_back(
        {{"gap_from", b.gap_lo}, {"gap_to", b.gap_hi}, {"count", b.count}, {"mean_m", b.mean}, {"median_m", b.median}});
  }
  return {{"distance_m", ToJson(r.distance)}, {"by_frame_gap", by_gap}, {"skipped", r.skipped}};
}

}  // namespace f2c
