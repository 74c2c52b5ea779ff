#include "f2c/refine/relations.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <unordered_map>

#include "f2c/util/error.h"

namespace f2c {

void RelationOptions::Check() const { CheckFields(*this); }

bool ClassifyRelation(double theta, const RelationOptions& options, RelationType* type, double* weight) {
  const double targets[kRelationTypeCount] = {0.0, M_PI, M_PI / 2};
  const RelationType types[kRelationTypeCount] = {RelationType::kParallel, RelationType::kAntiparallel,
                                                  RelationType::kOrthogonal};
  int best = 0;
  for (int k = 1; k < kRelationTypeCount; ++k) {
    if (std::abs(theta - targets[k]) < std::abs(theta - targets[best])) best = k;
  }
  const double off = theta - targets[best];
  const double sigma = options.sigma_deg * M_PI / 180;
  const double w = std::exp(-off * off / (2 * sigma * sigma));
  if (std::abs(off) > options.max_angle_deg * M_PI / 180 || w <= options.min_weight) return false;
  *type = types[best];
  *weight = w;
  return true;
}

namespace {

double TargetAngle(RelationType type) {
  switch (type) {
    case RelationType::kParallel:
      return 0;
    case RelationType::kAntiparallel:
      return M_PI;
    case RelationType::kOrthogonal:
      return M_PI / 2;
  }
  return 0;
}

uint64_t PairKey(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
}

}  // namespace

std::vector<PlaneRelation> DetectRelations(const ProxyHierarchy& h, const RelationOptions& options,
                                           RelationStats* stats) {
  options.Check();
  const StructureConstraints& s = h.structure;
  // In-image angles between parents that one frame sees both of: inlier-weighted sums.
  std::unordered_map<uint64_t, std::pair<double, double>> seen_together;
  if (options.covisible_tolerance_deg > 0) {
    int child = 0;
    const int children = static_cast<int>(s.children.size());
    while (child < children) {
      int end = child;
      while (end < children && s.children[end].frame == s.children[child].frame) ++end;
      for (int a = child; a < end; ++a) {
        for (int b = a; b < end; ++b) {
          const double w = std::min(s.children[a].share, s.children[b].share);
          const double angle = std::acos(std::clamp<double>(s.children[a].normal.dot(s.children[b].normal), -1, 1));
          for (int pa : h.child_parents[a]) {
            for (int pb : h.child_parents[b]) {
              if (pa == pb) continue;
              auto& [sum, weight] = seen_together[PairKey(pa, pb)];
              sum += w * angle;
              weight += w;
            }
          }
        }
      }
      child = end;
    }
  }

  RelationStats local;
  std::vector<PlaneRelation> relations;
  auto consider = [&](int a, int b) {
    const double cosine = std::clamp(s.parents[a].normal.dot(s.parents[b].normal), -1.0, 1.0);
    RelationType type;
    double weight;
    if (!ClassifyRelation(std::acos(cosine), options, &type, &weight)) return;
    if (options.covisible_tolerance_deg > 0) {
      const auto it = seen_together.find(PairKey(a, b));
      if (it != seen_together.end() && std::abs(it->second.first / it->second.second - TargetAngle(type)) >
                                           options.covisible_tolerance_deg * M_PI / 180) {
        local.dropped_covisible++;
        return;
      }
    }
    relations.push_back({a, b, type, static_cast<float>(weight)});
    local.by_type[static_cast<int>(type)]++;
  };
  const int windows = static_cast<int>(h.window_parents.size());
  for (int w = 0; w < windows; ++w) {
    const std::vector<int>& here = h.window_parents[w];
    for (size_t i = 0; i < here.size(); ++i) {
      for (size_t j = i + 1; j < here.size(); ++j) consider(here[i], here[j]);
    }
    if (options.adjacent_windows && w + 1 < windows) {
      for (int a : here) {
        for (int b : h.window_parents[w + 1]) consider(a, b);
      }
    }
  }
  if (options.max_per_parent > 0) {
    // Parents' support: the inliers of their children.
    std::vector<double> support(s.parents.size(), 0.0);
    for (const CoplanarLink& l : s.links) support[l.parent] += s.children[l.child].share;
    std::vector<std::pair<double, int>> order;
    for (size_t i = 0; i < relations.size(); ++i) {
      const PlaneRelation& r = relations[i];
      order.push_back({-r.weight * std::min(support[r.parent_a], support[r.parent_b]), static_cast<int>(i)});
    }
    std::sort(order.begin(), order.end());
    std::vector<int> count(s.parents.size(), 0);
    std::vector<PlaneRelation> kept;
    for (const auto& [score, i] : order) {
      const PlaneRelation& r = relations[i];
      if (count[r.parent_a] >= options.max_per_parent || count[r.parent_b] >= options.max_per_parent) {
        local.dropped_cap++;
        local.by_type[static_cast<int>(r.type)]--;
        continue;
      }
      count[r.parent_a]++;
      count[r.parent_b]++;
      kept.push_back(r);
    }
    relations = std::move(kept);
  }
  if (stats) *stats = local;
  return relations;
}

nlohmann::json ToJson(const RelationStats& s) {
  return {{"parallel", s.by_type[0]},
          {"antiparallel", s.by_type[1]},
          {"orthogonal", s.by_type[2]},
          {"dropped_covisible", s.dropped_covisible},
          {"dropped_cap", s.dropped_cap}};
}

}  // namespace f2c
