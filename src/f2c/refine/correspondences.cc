#include "f2c/refine/correspondences.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <numeric>
#include <nlohmann/json.hpp>

#include "f2c/refine/self_check.h"
#include "f2c/util/error.h"

namespace f2c {

void CorrespondenceOptions::Check() const {
  CheckFields(*this);
  if (initial_max_distance < final_max_distance) {
    ThrowInputError("--max-distance-final", fmt::format("must be <= --max-distance-initial ({}), got {}",
                                                        initial_max_distance, final_max_distance));
  }
  if (initial_max_angle_deg < final_max_angle_deg) {
    ThrowInputError("--max-angle-final", fmt::format("must be <= --max-angle-initial ({}), got {}",
                                                     initial_max_angle_deg, final_max_angle_deg));
  }
}

namespace {

Thresholds Blend(const CorrespondenceOptions& o, double t) {  // t = 1: initial, 0: final
  t = std::clamp(t, 0.0, 1.0);
  return {o.final_max_distance + t * (o.initial_max_distance - o.final_max_distance),
          (o.final_max_angle_deg + t * (o.initial_max_angle_deg - o.final_max_angle_deg)) * M_PI / 180.0};
}

uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace

Thresholds ThresholdsForAge(const CorrespondenceOptions& o, int age) {
  if (o.decay_iterations == 0) return Blend(o, 0.0);
  return Blend(o, 1.0 - static_cast<double>(age) / o.decay_iterations);
}

Thresholds ThresholdsForPath(const CorrespondenceOptions& o, double distance, double window_length) {
  if (!(window_length > 0)) return Blend(o, 1.0);
  return Blend(o, std::sqrt(std::max(distance, 0.0) / (window_length / 2)));
}

int CorrespondenceStats::total() const { return std::accumulate(by_type.begin(), by_type.end(), 0); }

std::vector<FeatureCorrespondence> FindCorrespondences(const std::vector<FramePair>& pairs, const FeatureIndex& index,
                                                       const PoseVector& poses, const WindowSchedule& schedule,
                                                       int iteration, const std::vector<double>& path,
                                                       const CorrespondenceOptions& options,
                                                       CorrespondenceStats* stats) {
  options.Check();
  const int n = static_cast<int>(poses.size());
  const int64_t per_frame =
      schedule.Polishing(iteration) && options.polish_per_frame > 0 ? options.polish_per_frame : options.per_frame;
  const int share = pairs.empty() ? 0
                                  : std::max<int>(options.min_per_pair,
                                                  static_cast<int>((per_frame * n + pairs.size() - 1) / pairs.size()));
  std::vector<std::vector<FeatureCorrespondence>> found(pairs.size());
  std::vector<int64_t> tried(pairs.size(), 0);
  tbb::parallel_for(0, static_cast<int>(pairs.size()), [&](int p) {
    const int a = pairs[p].a;
    const int b = pairs[p].b;
    Thresholds t;
    if (schedule.Polishing(iteration)) {
      t = {options.polish_max_distance, options.polish_max_angle_deg * M_PI / 180.0};
    } else if (options.schedule == ThresholdSchedule::kAge) {
      t = ThresholdsForAge(options, iteration - schedule.FirstShared(a, b));
    } else {
      // d and L in the windows' own unit: metres of path, or frames.
      const double distance = schedule.mode() == WindowMode::kPath ? path[b] - path[a] : b - a;
      t = ThresholdsForPath(options, distance, schedule.Length(iteration));
    }
    const float max_d2 = static_cast<float>(t.max_distance * t.max_distance);
    const float min_cos = static_cast<float>(std::cos(t.max_angle));
    const Eigen::Isometry3f world_from_a = poses[a].ToRigid().cast<float>();
    const Eigen::Isometry3f world_from_b = poses[b].ToRigid().cast<float>();
    std::vector<FeatureCorrespondence>& out = found[p];
    out.reserve(share);
    uint32_t nearest[64];
    float d2[64];
    for (int side = 0; side < 2; ++side) {
      const int source = side == 0 ? b : a;
      const int target = side == 0 ? a : b;
      const FrameIndex& src = *index.frames[source];
      const FrameIndex& dst = *index.frames[target];
      const Eigen::Isometry3f target_from_source =
          (side == 0 ? world_from_a : world_from_b).inverse() * (side == 0 ? world_from_b : world_from_a);
      const int want = side == 0 ? (share + 1) / 2 : share / 2;
      const int planes = src.families[0].size();
      const int total = planes + src.families[1].size();
      if (total == 0 || want == 0) continue;
      // A pseudo-random permutation of the source's features: offset + j step (mod total),
      // step coprime to total; seeded by the pair, the side and the iteration.
      uint64_t h = SplitMix64(options.seed ^ SplitMix64((static_cast<uint64_t>(iteration) << 42) ^
                                                        (static_cast<uint64_t>(a) << 21) ^ b ^ (side * 0x5bd1e995ULL)));
      const int64_t offset = static_cast<int64_t>(h % total);
      int64_t step = static_cast<int64_t>(SplitMix64(h) % total) | 1;
      while (std::gcd(step, static_cast<int64_t>(total)) != 1) step += 2;
      const int limit = std::min<int>(total, static_cast<int>(std::ceil(want * options.attempts)));
      int got = 0;
      for (int j = 0; j < limit && got < want; ++j) {
        const int i = static_cast<int>((offset + j * step) % total);
        const int family = i < planes ? 0 : 1;
        const int local = i < planes ? i : i - planes;
        const FeatureCloud& from = src.families[family];
        const FeatureCloud& to = dst.families[family];
        if (to.size() == 0) continue;
        if (family == 0 && HeldOut(source, local, options.held_out_every)) continue;
        ++tried[p];
        const Eigen::Vector3f q = target_from_source * from.point(local);
        const Eigen::Vector3f dir = target_from_source.linear() * from.direction(local);
        const int k = to.Nearest(q, options.neighbours, nearest, d2, max_d2);  // all within the distance
        for (int m = 0; m < k; ++m) {
          if (family == 0 && HeldOut(target, static_cast<int>(nearest[m]), options.held_out_every)) continue;
          const float c = to.direction(nearest[m]).dot(dir);
          if ((family == 0 ? c : std::abs(c)) < min_cos) continue;
          const FeatureType type = to.type(nearest[m]);
          const double w = options.type_weights[static_cast<int>(type)];
          if (w <= 0) break;
          FeatureCorrespondence corr;
          corr.target_frame = target;
          corr.point_frame = source;
          corr.kind = family == 0 ? CorrespondenceKind::kPointToPlane : CorrespondenceKind::kPointToLine;
          corr.feature_type = static_cast<uint8_t>(type);
          corr.weight = static_cast<float>(w);
          corr.target_point = to.point(nearest[m]);
          // The target's own normal (the paper). The symmetric point-to-plane normal, the mean
          // of both features', was no better on the real sequences and walks.
          corr.target_direction = to.direction(nearest[m]);
          corr.point = from.point(local);
          out.push_back(corr);
          ++got;
          break;
        }
      }
    }
  });
  std::vector<FeatureCorrespondence> all;
  size_t count = 0;
  for (const auto& f : found) count += f.size();
  all.reserve(count);
  CorrespondenceStats s;
  s.pairs = static_cast<int>(pairs.size());
  s.per_pair = share;
  for (size_t p = 0; p < found.size(); ++p) {
    s.pairs_matched += !found[p].empty();
    s.tried += tried[p];
    for (const FeatureCorrespondence& c : found[p]) ++s.by_type[c.feature_type];
    all.insert(all.end(), found[p].begin(), found[p].end());
  }
  if (stats) *stats = s;
  return all;
}

nlohmann::json ToJson(const CorrespondenceStats& s) {
  nlohmann::json by_type;
  for (int t = 0; t < kFeatureTypeCount; ++t) by_type[FeatureTypeName(static_cast<FeatureType>(t))] = s.by_type[t];
  return {{"pairs", s.pairs},       {"pairs_matched", s.pairs_matched},
          {"per_pair", s.per_pair}, {"tried", s.tried},
          {"total", s.total()},     {"by_type", by_type}};
}

}  // namespace f2c
