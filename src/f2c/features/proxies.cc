#include "f2c/features/proxies.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "f2c/util/error.h"

namespace f2c {

void ProxyOptions::Check() const { CheckFields(*this); }

namespace {

// The residual a flat cell may have at its depth: flat_noise_ratio sigma(z).
double NoiseBound(const PointGrid& g, int i, const ProxyOptions& o) {
  const double dz = g.points[i].z() - 0.4;
  return o.flat_noise_ratio * (o.sensor_sigma_a + o.sensor_sigma_b * dz * dz);
}

// A member's depth-noise covariance: sigma(z) along its ray (depth z moves the point by
// dz p / z), bearing_noise times its range across the ray.
Eigen::Matrix3d PointNoise(const Eigen::Vector3d& p, const ProxyOptions& o) {
  const double dz = p.z() - 0.4, sigma = o.sensor_sigma_a + o.sensor_sigma_b * dz * dz;
  const Eigen::Vector3d ray = p / p.z();
  const double range2 = p.squaredNorm(), across = o.bearing_noise * o.bearing_noise * range2;
  return sigma * sigma * ray * ray.transpose() + across * (Eigen::Matrix3d::Identity() - p * p.transpose() / range2);
}

}  // namespace

bool IsFlat(const PointGrid& g, int i, const ProxyOptions& o) {
  return g.HasNormal(i) && (g.curvature[i] <= o.max_curvature || g.residual[i] <= NoiseBound(g, i, o));
}

float Flatness(const PointGrid& g, int i, const ProxyOptions& o) {
  if (!IsFlat(g, i, o)) return 0.0f;
  const double bound = NoiseBound(g, i, o);
  const double by_noise = bound > 0 ? 1.0 - g.residual[i] / bound : (g.residual[i] == 0 ? 1.0 : 0.0);
  return static_cast<float>(std::clamp(std::max(1.0 - g.curvature[i] / o.max_curvature, by_noise), 0.0, 1.0));
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
  const int n = g.width * g.height;
  std::vector<uint8_t> flat(n);
  for (int i = 0; i < n; ++i) flat[i] = IsFlat(g, i, o);
  auto Member = [&](int i) { return flat[i] != 0; };
  // Reused between frames on a thread: a frame's clusters are megabytes, and fresh pages
  // cost more than filling them.
  thread_local std::vector<Cluster> clusters;
  clusters.assign(n, Cluster{});
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
  const double max_weight = 1.0 - std::cos(o.max_normal_angle_deg * M_PI / 180);
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

  const double cos_max = std::cos(o.max_normal_angle_deg * M_PI / 180);
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

  // Members of each large enough cluster, in cell order.
  std::vector<int> slot(n, -1);
  std::vector<std::vector<int>> members;
  for (int i = 0; i < n; ++i) {
    if (!Member(i)) continue;
    const int root = Find(clusters, i);
    if (clusters[root].count < o.min_points) continue;
    if (slot[root] < 0) slot[root] = static_cast<int>(members.size()), members.emplace_back();
    members[slot[root]].push_back(i);
  }

  struct Fit {
    Eigen::Vector3d centroid, normal;
    Eigen::Matrix3d covariance, axes, noise = Eigen::Matrix3d::Zero();
    double rms;
  };
  auto fit = [&](const std::vector<int>& cells) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
    for (int i : cells) {
      const Eigen::Vector3d p = g.points[i].cast<double>();
      sum += p;
      sum2 += p * p.transpose();
    }
    Fit f;
    f.centroid = sum / cells.size();
    f.covariance = sum2 / cells.size() - f.centroid * f.centroid.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(f.covariance);
    f.axes = eig.eigenvectors();
    f.normal = f.axes.col(0);
    if (f.normal.dot(f.centroid) > 0) f.normal = -f.normal;
    f.rms = std::sqrt(std::max(0.0, eig.eigenvalues()(0)));
    return f;
  };
  // covariance = spread + mu N in expectation, and spread n = 0 for the true normal n, so mu
  // is the smallest generalised eigenvalue of (covariance, N); covariance - mu N is then
  // positive semi-definite, singular along that n.
  const bool noisy = o.sensor_sigma_a > 0 || o.sensor_sigma_b > 0;
  auto estimate_noise = [&](const std::vector<int>& cells, const Eigen::Matrix3d& covariance) {
    Eigen::Matrix3d noise = Eigen::Matrix3d::Zero();
    for (int i : cells) noise += PointNoise(g.points[i].cast<double>(), o);
    noise /= cells.size();
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix3d> ges(covariance, noise, Eigen::EigenvaluesOnly);
    if (ges.info() != Eigen::Success) return Eigen::Matrix3d::Zero().eval();
    return (std::max(0.0, ges.eigenvalues()(0)) * noise).eval();
  };

  struct Result {
    Fit fit;
    std::vector<int> cells;
  };
  std::vector<Result> results;
  std::vector<double> distance;
  for (std::vector<int>& cells : members) {
    Fit f = fit(cells);
    for (int iteration = 0; iteration < o.trim_iterations; ++iteration) {
      distance.resize(cells.size());
      for (size_t k = 0; k < cells.size(); ++k) {
        distance[k] = std::abs(f.normal.dot(g.points[cells[k]].cast<double>() - f.centroid));
      }
      std::vector<double> sorted = distance;
      std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
      const double sigma = std::max(1.4826 * sorted[sorted.size() / 2], o.min_trim_sigma);
      std::vector<int> kept;
      for (size_t k = 0; k < cells.size(); ++k) {
        if (distance[k] <= o.trim_sigmas * sigma) kept.push_back(cells[k]);
      }
      if (kept.size() == cells.size()) break;
      cells = std::move(kept);
      if (static_cast<int>(cells.size()) < o.min_points) break;
      f = fit(cells);
    }
    if (static_cast<int>(cells.size()) < o.min_points) continue;
    // A proxy must span a surface, not a line of cells.
    const double width = std::sqrt(std::max(0.0, f.axes.col(1).dot(f.covariance * f.axes.col(1))));
    if (width < o.min_width) continue;
    if (noisy) f.noise = estimate_noise(cells, f.covariance);
    results.push_back({f, std::move(cells)});
  }
  // Largest first; ties keep cell order (the order of the clusters' first cells).
  std::stable_sort(results.begin(), results.end(),
                   [](const Result& a, const Result& b) { return a.cells.size() > b.cells.size(); });

  ProxySegmentation out;
  out.labels.assign(n, -1);
  for (const Result& r : results) {
    const int index = static_cast<int>(out.proxies.size());
    PlanarProxy p;
    p.normal = r.fit.normal.cast<float>();
    p.offset = static_cast<float>(r.fit.normal.dot(r.fit.centroid));
    p.centroid = r.fit.centroid.cast<float>();
    p.covariance = r.fit.covariance.cast<float>();
    p.noise = r.fit.noise.cast<float>();
    p.rms = static_cast<float>(r.fit.rms);
    p.inliers = static_cast<int32_t>(r.cells.size());
    for (int i : r.cells) {
      out.labels[i] = index;
      const Eigen::Vector3d d = g.points[i].cast<double>() - r.fit.centroid;
      p.extent.x() = std::max(p.extent.x(), static_cast<float>(std::abs(d.dot(r.fit.axes.col(2)))));
      p.extent.y() = std::max(p.extent.y(), static_cast<float>(std::abs(d.dot(r.fit.axes.col(1)))));
    }
    out.proxies.push_back(p);
  }
  return out;
}

}  // namespace f2c
