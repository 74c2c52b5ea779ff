#include "f2c/refine/hierarchy.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <nlohmann/json.hpp>
#include <numeric>
#include <queue>
#include <set>
#include <tuple>

#include "f2c/util/error.h"

namespace f2c {

void HierarchyOptions::Check() const { CheckFields(*this); }

namespace {

struct Cluster {
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid_sum = Eigen::Vector3d::Zero();
  double weight = 0;
  std::vector<int> members;
  std::vector<std::pair<int, int>> imaged;  // (image, item) of the members with an image, sorted
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  int version = 0;
  bool alive = true;

  void Add(const Cluster& other) {
    normal_sum += other.normal_sum;
    centroid_sum += other.centroid_sum;
    weight += other.weight;
    members.insert(members.end(), other.members.begin(), other.members.end());
    std::vector<std::pair<int, int>> both;
    both.reserve(imaged.size() + other.imaged.size());
    std::merge(imaged.begin(), imaged.end(), other.imaged.begin(), other.imaged.end(), std::back_inserter(both));
    imaged = std::move(both);
    Update();
  }
  void Update() {
    normal = normal_sum.normalized();
    centroid = centroid_sum / weight;
  }
};

Cluster FromItem(const ClusterItem& item, int index) {
  Cluster c;
  c.normal_sum = item.weight * item.normal;
  c.centroid_sum = item.weight * item.centroid;
  c.weight = item.weight;
  c.members = {index};
  if (item.image >= 0) c.imaged = {{item.image, index}};
  c.Update();
  return c;
}

// Whether two items of one image are one surface: within the merge angle, and each centroid
// within in_image_distance of the other's plane.
bool OneSurfaceInImage(const ClusterItem& a, const ClusterItem& b, const HierarchyOptions& options) {
  if (a.normal.dot(b.normal) < std::cos(options.max_normal_angle_deg * M_PI / 180)) return false;
  const Eigen::Vector3d d = b.centroid - a.centroid;
  return std::max(std::abs(a.normal.dot(d)), std::abs(b.normal.dot(d))) <= options.in_image_distance;
}

// Whether some image saw a member of each cluster as two separate surfaces.
bool SeparatedInSomeImage(const Cluster& a, const Cluster& b, const std::vector<ClusterItem>& items,
                          const HierarchyOptions& options) {
  if (options.in_image_distance <= 0) return false;
  size_t i = 0, j = 0;
  while (i < a.imaged.size() && j < b.imaged.size()) {
    const int image = a.imaged[i].first;
    if (image < b.imaged[j].first) {
      ++i;
    } else if (b.imaged[j].first < image) {
      ++j;
    } else {
      size_t j_end = j;
      while (j_end < b.imaged.size() && b.imaged[j_end].first == image) ++j_end;
      for (; i < a.imaged.size() && a.imaged[i].first == image; ++i) {
        for (size_t k = j; k < j_end; ++k) {
          if (!OneSurfaceInImage(items[a.imaged[i].second], items[b.imaged[k].second], options)) return true;
        }
      }
      j = j_end;
    }
  }
  return false;
}

// The merge cost of two clusters, or infinity when they may not merge under the thresholds
// scaled by `fraction`, or when an image saw them apart.
double MergeCost(const Cluster& a, const Cluster& b, const std::vector<ClusterItem>& items,
                 const HierarchyOptions& options, double fraction) {
  const double max_angle = fraction * options.max_normal_angle_deg * M_PI / 180;
  const double max_distance = fraction * options.max_distance;
  const double cosine = a.normal.dot(b.normal);
  if (cosine < std::cos(max_angle)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector3d d = b.centroid - a.centroid;
  const double distance = std::max(std::abs(a.normal.dot(d)), std::abs(b.normal.dot(d)));
  if (distance > max_distance) return std::numeric_limits<double>::infinity();
  if (SeparatedInSomeImage(a, b, items, options)) return std::numeric_limits<double>::infinity();
  return distance / max_distance + std::acos(std::min(1.0, cosine)) / max_angle;
}

// The value below which half the weight lies (values and weights paired; sorts them).
double WeightedMedian(std::vector<std::pair<double, double>>* values) {
  std::sort(values->begin(), values->end());
  double total = 0;
  for (const auto& [v, w] : *values) total += w;
  double below = 0;
  for (const auto& [v, w] : *values) {
    below += w;
    if (below >= 0.5 * total) return v;
  }
  return values->back().first;
}

}  // namespace

std::vector<double> SiblingAgreement(const std::vector<ClusterItem>& items, const PlaneCluster& cluster,
                                     const HierarchyOptions& options) {
  std::vector<double> agreement(cluster.members.size(), 1.0);
  if (options.agreement_scale <= 0 || static_cast<int>(cluster.members.size()) < options.agreement_min_children) {
    return agreement;
  }
  std::vector<double> along(cluster.members.size());
  std::vector<std::pair<double, double>> weighted;
  weighted.reserve(along.size());
  for (size_t i = 0; i < along.size(); ++i) {
    const ClusterItem& item = items[cluster.members[i]];
    along[i] = cluster.normal.dot(item.centroid);
    weighted.emplace_back(along[i], item.weight);
  }
  const double median = WeightedMedian(&weighted);
  for (size_t i = 0; i < along.size(); ++i)
    weighted[i] = {std::abs(along[i] - median), items[cluster.members[i]].weight};
  const double spread = std::max(options.agreement_floor, 1.4826 * WeightedMedian(&weighted));
  const double scale = options.agreement_scale * spread;
  for (size_t i = 0; i < along.size(); ++i) {
    const double t = (along[i] - median) / scale;
    agreement[i] = 1 / (1 + t * t);
  }
  return agreement;
}

std::vector<PlaneCluster> ClusterCoplanar(const std::vector<ClusterItem>& items, const HierarchyOptions& options) {
  // First pass: largest first, each into the best agreeing cluster within the tighter
  // thresholds, or a new one.
  std::vector<int> order(items.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return items[a].weight > items[b].weight; });
  std::vector<Cluster> clusters;
  for (int i : order) {
    const Cluster single = FromItem(items[i], i);
    double best = std::numeric_limits<double>::infinity();
    int best_k = -1;
    for (int k = 0; k < static_cast<int>(clusters.size()); ++k) {
      const double cost = MergeCost(clusters[k], single, items, options, options.premerge_fraction);
      if (cost < best) best = cost, best_k = k;
    }
    if (best_k < 0) {
      clusters.push_back(single);
    } else {
      clusters[best_k].Add(single);
    }
  }

  // Agglomerative: the best-agreeing pair merges first, until none may.
  using Candidate = std::tuple<double, int, int, int, int>;  // cost, a, b, versions of a and b
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue;
  const int k = static_cast<int>(clusters.size());
  for (int a = 0; a < k; ++a) {
    for (int b = a + 1; b < k; ++b) {
      const double cost = MergeCost(clusters[a], clusters[b], items, options, 1.0);
      if (std::isfinite(cost)) queue.emplace(cost, a, b, 0, 0);
    }
  }
  while (!queue.empty()) {
    const auto [cost, a, b, va, vb] = queue.top();
    queue.pop();
    if (!clusters[a].alive || !clusters[b].alive || clusters[a].version != va || clusters[b].version != vb) continue;
    clusters[a].Add(clusters[b]);
    clusters[a].version++;
    clusters[b].alive = false;
    for (int c = 0; c < k; ++c) {
      if (c == a || !clusters[c].alive) continue;
      const double next = MergeCost(clusters[a], clusters[c], items, options, 1.0);
      if (!std::isfinite(next)) continue;
      if (c < a) {
        queue.emplace(next, c, a, clusters[c].version, clusters[a].version);
      } else {
        queue.emplace(next, a, c, clusters[a].version, clusters[c].version);
      }
    }
  }

  std::vector<PlaneCluster> result;
  for (Cluster& c : clusters) {
    if (!c.alive) continue;
    PlaneCluster p;
    p.normal = c.normal;
    p.centroid = c.centroid;
    p.weight = c.weight;
    p.members = std::move(c.members);
    std::sort(p.members.begin(), p.members.end());
    result.push_back(std::move(p));
  }
  std::sort(result.begin(), result.end(), [](const PlaneCluster& a, const PlaneCluster& b) {
    if (a.weight != b.weight) return a.weight > b.weight;
    return a.members.front() < b.members.front();
  });
  return result;
}

ChildProxy MakeChild(int frame, const PlanarProxy& p, bool remove_noise) {
  ChildProxy c;
  c.frame = frame;
  c.normal = p.normal;
  c.offset = p.offset;
  c.centroid = p.centroid;
  c.covariance = p.covariance;
  c.share = static_cast<float>(p.inliers);
  if (remove_noise && !p.noise.isZero()) {
    // covariance - noise is positive semi-definite and singular along the noise-free normal
    // (features/proxies.h); the plane goes through the same centroid.
    c.covariance = p.covariance - p.noise;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig(c.covariance);
    c.normal = eig.eigenvectors().col(0).normalized();
    if (c.normal.dot(p.normal) < 0) c.normal = -c.normal;
    c.offset = c.normal.dot(c.centroid);
  }
  return c;
}

ProxyHierarchy BuildProxyHierarchy(const WindowSchedule& schedule, int iteration, const FeatureIndex& index,
                                   const PoseVector& poses, const HierarchyOptions& options) {
  options.Check();
  ProxyHierarchy h;
  StructureConstraints& s = h.structure;
  const int n = static_cast<int>(index.frames.size());
  F2C_CHECK(static_cast<int>(poses.size()) == n, "one pose per frame");
  // Children, and where the current poses put them.
  std::vector<int> first_child(n + 1, 0);
  std::vector<ClusterItem> world;
  for (int f = 0; f < n; ++f) {
    first_child[f] = static_cast<int>(s.children.size());
    const Rigid3d pose = poses[f].ToRigid();
    for (const PlanarProxy& p : index.frames[f]->proxies) {
      const ChildProxy c = MakeChild(f, p, options.remove_proxy_noise);
      s.children.push_back(c);
      ClusterItem item;
      item.normal = (pose.linear() * c.normal.cast<double>()).normalized();
      item.centroid = pose * p.centroid.cast<double>();
      item.weight = p.inliers;
      item.image = f;
      world.push_back(item);
    }
  }
  first_child[n] = static_cast<int>(s.children.size());
  h.child_parents.resize(s.children.size());

  const std::vector<Window> windows = schedule.Windows(iteration);
  h.window_parents.resize(windows.size());
  for (size_t w = 0; w < windows.size(); ++w) {
    const int begin = first_child[windows[w].begin], end = first_child[windows[w].end];
    const std::vector<ClusterItem> items(world.begin() + begin, world.begin() + end);
    for (const PlaneCluster& cluster : ClusterCoplanar(items, options)) {
      const int parent = static_cast<int>(s.parents.size());
      s.parents.push_back({cluster.normal, cluster.offset(), cluster.centroid});
      h.parent_window.push_back(static_cast<int>(w));
      h.window_parents[w].push_back(parent);
      std::set<int> frames;
      const std::vector<double> agreement = SiblingAgreement(items, cluster, options);
      for (size_t i = 0; i < cluster.members.size(); ++i) {
        const int child = begin + cluster.members[i];
        s.links.push_back({child, parent, world[child].centroid, static_cast<float>(world[child].weight),
                           static_cast<float>(agreement[i])});
        h.child_parents[child].push_back(parent);
        frames.insert(s.children[child].frame);
        if (agreement[i] < 0.5) h.stats.links_discounted++;
      }
      if (frames.size() >= 2) h.stats.parents_spanning_frames++;
    }
  }
  h.stats.children = static_cast<int>(s.children.size());
  h.stats.parents = static_cast<int>(s.parents.size());
  h.stats.links = static_cast<int>(s.links.size());
  h.stats.agreement_scale = options.agreement_scale;
  return h;
}

double ChildNormalSpreadDeg(const StructureConstraints& s, const PoseVector& poses) {
  double sum = 0, weight = 0;
  for (const CoplanarLink& l : s.links) {
    const ChildProxy& c = s.children[l.child];
    const Eigen::Vector3d n = poses[c.frame].rotation * c.normal.cast<double>();
    const double cosine = std::clamp(n.normalized().dot(s.parents[l.parent].normal.normalized()), -1.0, 1.0);
    const double angle = std::acos(cosine);
    sum += l.weight * angle * angle;
    weight += l.weight;
  }
  return weight > 0 ? std::sqrt(sum / weight) * 180 / M_PI : 0.0;
}

nlohmann::json ToJson(const HierarchyStats& s) {
  return {{"children", s.children},
          {"parents", s.parents},
          {"parents_spanning_frames", s.parents_spanning_frames},
          {"links", s.links},
          {"links_discounted", s.links_discounted},
          {"agreement_scale", s.agreement_scale}};
}

}  // namespace f2c
