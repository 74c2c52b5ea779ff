#include "f2c/features/proxies.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "f2c/util/error.h"

namespace f2c {

void ProxyOptions::Check() const {
  auto fail = [](const std::string& field, const std::string& what) { ThrowInputError("proxies." + field, what); };
  if (min_points < 3) fail("min_points", "must be >= 3");
  if (!(max_distance > 0)) fail("max_distance", "must be positive");
  if (!(max_normal_angle > 0 && max_normal_angle < M_PI / 2)) fail("max_normal_angle", "must be in (0, pi/2)");
  if (!(max_rms_a > 0 && max_rms_b >= 0)) fail("max_rms", "need max_rms_a > 0 and max_rms_b >= 0");
  if (!(max_curvature > 0)) fail("max_curvature", "must be positive");
  if (!(min_width >= 0)) fail("min_width", "must be >= 0");
}

namespace {

struct Cluster {
  int parent = 0;
  int count = 0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();

  Eigen::Vector3d Centroid() const { return sum / count; }
  Eigen::Vector3d MeanNormal() const { return normal_sum.normalized(); }
};

int Find(std::vector<Cluster>& c, int i) {
  while (c[i].parent != i) {
    c[i].parent = c[c[i].parent].parent;  // path halving
    i = c[i].parent;
  }
  return i;
}

struct Edge {
  int a, b;
};

}  // namespace

ProxySegmentation ExtractProxies(const PointGrid& g, const ProxyOptions& o) {
  o.Check();
  const int n = g.width * g.height;
  auto Member = [&](int i) { return g.HasNormal(i) && g.curvature[i] <= o.max_curvature; };
  std::vector<Cluster> clusters(n);
  for (int i = 0; i < n; ++i) {
    clusters[i].parent = i;
    if (!Member(i)) continue;
    const Eigen::Vector3d p = g.points[i].cast<double>();
    clusters[i].count = 1;
    clusters[i].sum = p;
    clusters[i].sum2 = p * p.transpose();
    clusters[i].normal_sum = g.normals[i].cast<double>();
  }

  // Neighbour pairs, bucketed by 1 - cos(angle between the cells' normals): a counting sort,
  // stable, so the merge order (and the result) is the same on every run.
  const double max_weight = 1.0 - std::cos(o.max_normal_angle);
  constexpr int kBuckets = 256;
  std::vector<std::vector<Edge>> buckets(kBuckets);
  auto consider = [&](int a, int b) {
    if (!Member(a) || !Member(b)) return;
    const double w = 1.0 - static_cast<double>(g.normals[a].dot(g.normals[b]));
    if (w > max_weight) return;
    const Eigen::Vector3f d = g.points[b] - g.points[a];
    if (std::abs(g.normals[a].dot(d)) > o.max_distance || std::abs(g.normals[b].dot(d)) > o.max_distance) return;
    const int bucket = std::min(kBuckets - 1, static_cast<int>(w / max_weight * kBuckets));
    buckets[bucket].push_back({a, b});
  };
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int i = g.Index(x, y);
      if (x + 1 < g.width) consider(i, i + 1);
      if (y + 1 < g.height) consider(i, i + g.width);
    }
  }

  const double cos_max = std::cos(o.max_normal_angle);
  for (const auto& bucket : buckets) {
    for (const Edge& e : bucket) {
      int ra = Find(clusters, e.a), rb = Find(clusters, e.b);
      if (ra == rb) continue;
      Cluster& a = clusters[ra];
      Cluster& b = clusters[rb];
      const Eigen::Vector3d na = a.MeanNormal(), nb = b.MeanNormal();
      if (na.dot(nb) < cos_max) continue;
      const Eigen::Vector3d ca = a.Centroid(), cb = b.Centroid();
      if (std::abs(na.dot(cb - ca)) > o.max_distance || std::abs(nb.dot(ca - cb)) > o.max_distance) continue;
      const int count = a.count + b.count;
      const Eigen::Vector3d c = (a.sum + b.sum) / count;
      const Eigen::Vector3d nm = (a.normal_sum + b.normal_sum).normalized();
      const double variance = nm.dot(((a.sum2 + b.sum2) / count - c * c.transpose()) * nm);
      const double max_rms = o.max_rms_a + o.max_rms_b * c.z() * c.z();
      if (variance > max_rms * max_rms) continue;
      // Union by size; ties to the lower index, for determinism.
      if (b.count > a.count || (b.count == a.count && rb < ra)) std::swap(ra, rb);
      Cluster& root = clusters[ra];
      const Cluster& child = clusters[rb];
      root.count = count;
      root.sum += child.sum;
      root.sum2 += child.sum2;
      root.normal_sum += child.normal_sum;
      clusters[rb].parent = ra;
    }
  }

  // Proxies: large enough clusters, largest first (ties: the lower root cell).
  std::vector<int> roots;
  for (int i = 0; i < n; ++i) {
    if (clusters[i].parent == i && clusters[i].count >= o.min_points) roots.push_back(i);
  }
  std::stable_sort(roots.begin(), roots.end(), [&](int a, int b) { return clusters[a].count > clusters[b].count; });
  std::vector<int> proxy_of_root(n, -1);
  ProxySegmentation out;
  out.labels.assign(n, -1);
  std::vector<Eigen::Matrix3d> axes;
  for (int root : roots) {
    const Cluster& c = clusters[root];
    const Eigen::Vector3d centroid = c.Centroid();
    const Eigen::Matrix3d cov = c.sum2 / c.count - centroid * centroid.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    if (std::sqrt(std::max(0.0, eig.eigenvalues()(1))) < o.min_width) continue;
    Eigen::Vector3d normal = eig.eigenvectors().col(0);
    if (normal.dot(centroid) > 0) normal = -normal;
    PlanarProxy p;
    p.normal = normal.cast<float>();
    p.offset = static_cast<float>(normal.dot(centroid));
    p.centroid = centroid.cast<float>();
    p.covariance = cov.cast<float>();
    p.rms = static_cast<float>(std::sqrt(std::max(0.0, eig.eigenvalues()(0))));
    p.inliers = c.count;
    proxy_of_root[root] = static_cast<int>(out.proxies.size());
    out.proxies.push_back(p);
    axes.push_back(eig.eigenvectors());
  }
  for (int i = 0; i < n; ++i) {
    if (!Member(i)) continue;
    const int proxy = proxy_of_root[Find(clusters, i)];
    if (proxy < 0) continue;
    out.labels[i] = proxy;
    PlanarProxy& p = out.proxies[proxy];
    const Eigen::Vector3d d = (g.points[i] - p.centroid).cast<double>();
    const Eigen::Matrix3d& axis = axes[proxy];
    p.extent.x() = std::max(p.extent.x(), static_cast<float>(std::abs(d.dot(axis.col(2)))));
    p.extent.y() = std::max(p.extent.y(), static_cast<float>(std::abs(d.dot(axis.col(1)))));
  }
  return out;
}

}  // namespace f2c
