#include "f2c/refine/spanning_tree.h"

#include <algorithm>
#include <numeric>

#include "f2c/util/error.h"

namespace f2c {
namespace {

class UnionFind {
 public:
  explicit UnionFind(int n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int Find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  bool Join(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a == b) return false;
    parent_[std::max(a, b)] = std::min(a, b);
    return true;
  }

 private:
  std::vector<int> parent_;
};

struct Edge {
  int a, b;
  Rigid3d a_from_b;
  double confidence;
  int order;  // odometry links first among equals, then loops in their order: deterministic
};

}  // namespace

PoseVector SpanningTreePoses(const PoseVector& poses, const std::vector<double>& link_confidence,
                             const std::vector<LoopEdge>& loops, const std::vector<int>& link_from) {
  const int n = static_cast<int>(poses.size());
  F2C_CHECK(static_cast<int>(link_confidence.size()) + 1 == n || n == 0, "one confidence per frame after the first");
  F2C_CHECK(link_from.empty() || link_from.size() == link_confidence.size(), "one link source per link");
  std::vector<Edge> edges;
  for (int k = 1; k < n; ++k) {
    const int from = link_from.empty() ? k - 1 : link_from[k - 1];
    F2C_CHECK(from >= 0 && from < k, "a link joins a frame to an earlier one");
    edges.push_back({from, k, poses[from].ToRigid().inverse() * poses[k].ToRigid(), link_confidence[k - 1], k});
  }
  for (size_t i = 0; i < loops.size(); ++i) {
    const LoopEdge& l = loops[i];
    F2C_CHECK(l.frame_a >= 0 && l.frame_a < n && l.frame_b >= 0 && l.frame_b < n, "loop frames in range");
    edges.push_back({l.frame_a, l.frame_b, l.a_from_b, l.confidence, n + static_cast<int>(i)});
  }
  std::stable_sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.confidence != y.confidence ? x.confidence > y.confidence : x.order < y.order;
  });
  UnionFind components(n);
  std::vector<std::vector<std::pair<int, int>>> tree(n);  // neighbour, edge index
  for (int e = 0; e < static_cast<int>(edges.size()); ++e) {
    if (components.Join(edges[e].a, edges[e].b)) {
      tree[edges[e].a].push_back({edges[e].b, e});
      tree[edges[e].b].push_back({edges[e].a, e});
    }
  }
  PoseVector out = poses;
  std::vector<char> placed(n, 0);
  std::vector<int> stack = {0};
  placed[0] = 1;
  while (!stack.empty()) {
    const int u = stack.back();
    stack.pop_back();
    const Rigid3d world_from_u = out[u].ToRigid();
    for (const auto& [v, e] : tree[u]) {
      if (placed[v]) continue;
      const Edge& edge = edges[e];
      const Rigid3d u_from_v = edge.a == u ? edge.a_from_b : edge.a_from_b.inverse();
      out[v] = Pose::FromRigid(world_from_u * u_from_v);
      placed[v] = 1;
      stack.push_back(v);
    }
  }
  return out;
}

double LoopDisagreement(const PoseVector& poses, const std::vector<LoopEdge>& loops, int newest, double lever) {
  std::vector<double> e;
  for (size_t k = loops.size() - std::min<size_t>(loops.size(), std::max(0, newest)); k < loops.size(); ++k) {
    const LoopEdge& edge = loops[k];
    const Rigid3d a_from_b = poses[edge.frame_a].ToRigid().inverse() * poses[edge.frame_b].ToRigid();
    const Rigid3d off = a_from_b.inverse() * edge.a_from_b;
    e.push_back(std::max(off.translation().norm(), lever * Eigen::AngleAxisd(off.linear()).angle()));
  }
  if (e.empty()) return 0;
  std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
  return e[e.size() / 2];
}

}  // namespace f2c
