#include "f2c/eval/mesh_error.h"

#include <nanoflann.hpp>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "f2c/geometry/coord_table.h"
#include "f2c/util/error.h"

namespace f2c {

void MeshErrorOptions::Check() const { CheckFields(*this); }

double PointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  // The closest point by the region p projects into (Ericson, Real-Time Collision
  // Detection, 5.1.5): a corner, an edge, or the face.
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

namespace {

// True triangles bucketed in a grid of `cell`-sized cubes, each triangle in every cell its
// bounding box (grown by `reach`) touches: a point's cell then lists every triangle within
// `reach` of it.
class TriangleGrid {
 public:
  TriangleGrid(const PlyPoints& truth, double cell, double reach) : truth_(truth), cell_(cell) {
    for (int t = 0; t < static_cast<int>(truth.faces.size()); ++t) {
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
      for (int32_t v : truth.faces[t]) {
        lo = lo.cwiseMin(truth.positions[v].cast<double>());
        hi = hi.cwiseMax(truth.positions[v].cast<double>());
      }
      const Eigen::Vector3i a = Cell(lo.array() - reach), b = Cell(hi.array() + reach);
      for (int z = a.z(); z <= b.z(); ++z) {
        for (int y = a.y(); y <= b.y(); ++y) {
          for (int x = a.x(); x <= b.x(); ++x) cells_[PackCoords({x, y, z})].push_back(t);
        }
      }
    }
  }

  // Distance to the nearest triangle listed in p's cell; `fallback` when none is.
  double Distance(const Eigen::Vector3d& p, double fallback) const {
    const auto it = cells_.find(PackCoords(Cell(p)));
    if (it == cells_.end()) return fallback;
    double best = fallback;
    for (int t : it->second) {
      const auto& f = truth_.faces[t];
      best = std::min(
          best, PointTriangleDistance(p, truth_.positions[f[0]].cast<double>(), truth_.positions[f[1]].cast<double>(),
                                      truth_.positions[f[2]].cast<double>()));
    }
    return best;
  }

 private:
  Eigen::Vector3i Cell(const Eigen::Vector3d& p) const { return (p / cell_).array().floor().cast<int>(); }
  const PlyPoints& truth_;
  double cell_;
  std::unordered_map<uint64_t, std::vector<int>> cells_;
};

struct VertexCloud {
  const std::vector<Eigen::Vector3f>& points;
  size_t kdtree_get_point_count() const { return points.size(); }
  float kdtree_get_pt(size_t i, size_t dim) const { return points[i][static_cast<int>(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

}  // namespace

MeshError EvaluateMesh(const PlyPoints& mesh, const PlyPoints& truth, const MeshErrorOptions& o) {
  o.Check();
  if (truth.faces.empty()) ThrowInputError("true surfaces", "the PLY has no triangles");
  MeshError out;
  // Accuracy: every mesh vertex against the true triangles near it.
  const TriangleGrid grid(truth, o.max_distance, o.max_distance);
  std::vector<double> distance(mesh.positions.size());
  tbb::parallel_for(size_t{0}, mesh.positions.size(),
                    [&](size_t i) { distance[i] = grid.Distance(mesh.positions[i].cast<double>(), o.max_distance); });
  if (!distance.empty()) {
    out.far_fraction = static_cast<double>(std::count_if(distance.begin(), distance.end(),
                                                         [&](double d) { return d >= o.max_distance; })) /
                       static_cast<double>(distance.size());
    std::vector<double> sorted = distance;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() * 9 / 10), sorted.end());
    out.p90 = sorted[sorted.size() * 9 / 10];
    out.accuracy = ComputeStatistics(std::move(distance));
  }

  // Completeness: the true surface sampled on a grid in each triangle's plane (one sample
  // per spacing^2 of area, deterministic), each looked up in a k-d tree of the mesh's vertices.
  std::vector<Eigen::Vector3d> samples;
  for (const auto& f : truth.faces) {
    const Eigen::Vector3d a = truth.positions[f[0]].cast<double>(), b = truth.positions[f[1]].cast<double>(),
                          c = truth.positions[f[2]].cast<double>();
    const int n = std::max(1, static_cast<int>(std::ceil(std::max((b - a).norm(), (c - a).norm()) / o.sample_spacing)));
    // Barycentric lattice (i + 1/3, j + 1/3) / n with i + j < n: triangle centres of the
    // triangle cut into n^2 similar ones.
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        const double u = (i + 1.0 / 3.0) / n, v = (j + 1.0 / 3.0) / n;
        samples.push_back(a + u * (b - a) + v * (c - a));
      }
    }
  }
  out.surface_samples = static_cast<int>(samples.size());
  if (mesh.positions.empty() || samples.empty()) return out;
  VertexCloud cloud{mesh.positions};
  nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, VertexCloud>, VertexCloud, 3, uint32_t> tree(
      3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12));
  const float r2 = static_cast<float>(o.completeness_distance * o.completeness_distance);
  std::vector<uint8_t> covered(samples.size(), 0);
  tbb::parallel_for(size_t{0}, samples.size(), [&](size_t i) {
    const Eigen::Vector3f q = samples[i].cast<float>();
    uint32_t index = 0;
    float d2 = 0;
    tree.knnSearch(q.data(), 1, &index, &d2);
    covered[i] = d2 <= r2;
  });
  out.completeness = static_cast<double>(std::count(covered.begin(), covered.end(), 1)) / samples.size();
  return out;
}

}  // namespace f2c
