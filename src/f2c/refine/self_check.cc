#include "f2c/refine/self_check.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "f2c/refine/windows.h"
#include "f2c/util/error.h"

namespace f2c {

void SelfCheckOptions::Check() const { CheckFields(*this); }

bool HeldOut(int frame, int feature, int every) {
  if (every <= 0) return false;
  uint64_t h = (static_cast<uint64_t>(frame) << 32) ^ static_cast<uint32_t>(feature);
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdULL;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ULL;
  h ^= h >> 33;
  return h % static_cast<uint64_t>(every) == 0;
}

double SelfCheckScore::Rms() const { return std::sqrt(score); }

std::vector<PairShare> SharesOfPairs(const std::vector<FramePair>& pairs, const FeatureIndex& index,
                                     const PoseVector& poses, const CameraIntrinsics& k,
                                     const SelfCheckOptions& options, double max_depth, const std::vector<char>* skip) {
  std::vector<PairShare> partial(pairs.size());
  const float tau2 = static_cast<float>(options.tau * options.tau);
  const float radius2 = static_cast<float>(options.search_radius * options.search_radius);
  const float min_cos = static_cast<float>(std::cos(options.max_angle_deg * M_PI / 180));
  tbb::parallel_for(0, static_cast<int>(pairs.size()), [&](int p) {
    if (skip != nullptr && (*skip)[p]) return;
    uint32_t nearest[64];
    float d2[64];
    PairShare& out = partial[p];
    for (int side = 0; side < 2; ++side) {
      const int source = side == 0 ? pairs[p].a : pairs[p].b;
      const int target = side == 0 ? pairs[p].b : pairs[p].a;
      const FeatureCloud& from = index.frames[source]->family(FeatureFamily::kPlane);
      const FeatureCloud& to = index.frames[target]->family(FeatureFamily::kPlane);
      const Eigen::Isometry3f target_from_source =
          (poses[target].ToRigid().inverse() * poses[source].ToRigid()).cast<float>();
      // From a start that depends on the pair, so that a frame's pairs measure different
      // held-out features, the same ones before and after an iteration.
      const int size = from.size();
      const int start = size > 0 ? static_cast<int>((static_cast<uint64_t>(pairs[p].a) * 0x9E3779B1u +
                                                     static_cast<uint64_t>(pairs[p].b) * 0x85EBCA77u) %
                                                    size)
                                 : 0;
      int measured = 0;
      for (int j = 0; j < size && measured < options.points_per_pair; ++j) {
        const int i = (start + j) % size;
        if (!HeldOut(source, i, options.every)) continue;
        const Eigen::Vector3f q = target_from_source * from.point(i);
        if (!(q.z() > 0) || q.z() > max_depth) continue;
        const double u = k.fx * q.x() / q.z() + k.cx, v = k.fy * q.y() / q.z() + k.cy;
        if (u < 0 || v < 0 || u > k.width - 1 || v > k.height - 1) continue;
        ++out.points;
        ++measured;
        const Eigen::Vector3f n = target_from_source.linear() * from.direction(i);
        float best = tau2;
        const int found = to.size() > 0 ? to.Nearest(q, options.neighbours, nearest, d2, radius2) : 0;
        for (int m = 0; m < found; ++m) {
          if (to.direction(nearest[m]).dot(n) < min_cos) continue;
          const float d = to.direction(nearest[m]).dot(q - to.point(nearest[m]));
          best = std::min(best, d * d);
          break;
        }
        out.sum += best;
        out.agreeing += best < tau2;
      }
    }
  });
  return partial;
}

SelfCheckScore SumShares(const std::vector<PairShare>& shares, int pairs) {
  SelfCheckScore s;
  double sum = 0;
  for (const PairShare& p : shares) {  // in pair order: the same sum for any thread count
    sum += p.sum;
    s.points += p.points;
    s.agreeing += p.agreeing;
  }
  s.pairs = pairs;
  s.score = s.points > 0 ? sum / s.points : 0;
  return s;
}

SelfCheckScore ScoreHeldOut(const std::vector<FramePair>& pairs, const FeatureIndex& index, const PoseVector& poses,
                            const CameraIntrinsics& k, const SelfCheckOptions& options, double max_depth) {
  return SumShares(SharesOfPairs(pairs, index, poses, k, options, max_depth), static_cast<int>(pairs.size()));
}

std::vector<FramePair> WholeScanPairs(const FeatureIndex& index, const PoseVector& poses,
                                      const CameraIntrinsics& intrinsics, const PairOptions& options) {
  WindowOptions whole;
  whole.fine_to_coarse = false;
  whole.extra_iterations = 0;
  whole.polish_iterations = 0;
  const WindowSchedule schedule(whole, std::vector<double>(poses.size(), 0.0));
  return CandidatePairs(schedule, 0, index, poses, intrinsics, options);
}

std::vector<FramePair> UnitePairs(std::vector<FramePair> a, const std::vector<FramePair>& b) {
  a.insert(a.end(), b.begin(), b.end());
  auto key = [](const FramePair& p) { return std::pair(p.a, p.b); };
  std::sort(a.begin(), a.end(), [&](const FramePair& x, const FramePair& y) { return key(x) < key(y); });
  a.erase(std::unique(a.begin(), a.end(), [&](const FramePair& x, const FramePair& y) { return key(x) == key(y); }),
          a.end());
  return a;
}

namespace {

bool SamePoses(const PoseVector& a, const PoseVector& b) {
  auto same = [](const Pose& x, const Pose& y) {
    return x.translation == y.translation && x.rotation.coeffs() == y.rotation.coeffs();
  };
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), same);
}

}  // namespace

std::vector<FramePair> CheckPairCache::For(const FeatureIndex& index, const PoseVector& query,
                                           const CameraIntrinsics& intrinsics, const PairOptions& options) const {
  if (SamePoses(query, poses)) return pairs;
  return WholeScanPairs(index, query, intrinsics, options);
}

std::vector<PairShare> CheckPairCache::Shares(const std::vector<FramePair>& check, const FeatureIndex& index,
                                              const PoseVector& query, const CameraIntrinsics& intrinsics,
                                              const SelfCheckOptions& options, double max_depth) const {
  if (!SamePoses(query, poses) || scored.empty()) {
    return SharesOfPairs(check, index, query, intrinsics, options, max_depth);
  }
  // Both lists sorted by (a, b): one merge finds each kept share.
  std::vector<char> known(check.size(), 0);
  std::vector<PairShare> kept(check.size());
  auto key = [](const FramePair& p) { return std::pair(p.a, p.b); };
  for (size_t i = 0, j = 0; i < check.size(); ++i) {
    while (j < scored.size() && key(scored[j]) < key(check[i])) ++j;
    if (j < scored.size() && key(scored[j]) == key(check[i])) {
      known[i] = 1;
      kept[i] = shares[j];
    }
  }
  std::vector<PairShare> fresh = SharesOfPairs(check, index, query, intrinsics, options, max_depth, &known);
  for (size_t i = 0; i < check.size(); ++i) {
    if (known[i]) fresh[i] = kept[i];
  }
  return fresh;
}

void CheckPairCache::Keep(const PoseVector& kept_poses, std::vector<FramePair> kept_pairs,
                          std::vector<FramePair> kept_scored, std::vector<PairShare> kept_shares) {
  F2C_CHECK(kept_scored.size() == kept_shares.size(), "one share per scored pair");
  poses = kept_poses;
  pairs = std::move(kept_pairs);
  scored = std::move(kept_scored);
  shares = std::move(kept_shares);
}

nlohmann::json ToJson(const SelfCheckRecord& r) {
  if (!r.done) return nullptr;
  auto score = [](const SelfCheckScore& s) {
    return nlohmann::json{{"rms_m", s.Rms()},
                          {"points", s.points},
                          {"agreeing", s.points > 0 ? nlohmann::json(static_cast<double>(s.agreeing) / s.points)
                                                    : nlohmann::json(nullptr)}};
  };
  return {{"pairs", r.before.pairs}, {"before", score(r.before)}, {"after", score(r.after)}, {"undone", r.undone}};
}

}  // namespace f2c
