#include "f2c/features/depth_features.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "f2c/geometry/coord_table.h"
#include "f2c/util/error.h"

namespace f2c {

const char* FeatureTypeName(FeatureType type) {
  switch (type) {
    case FeatureType::kPlane:
      return "plane";
    case FeatureType::kSilhouette:
      return "silhouette";
    case FeatureType::kShadow:
      return "shadow";
    case FeatureType::kBorder:
      return "border";
    case FeatureType::kRidge:
      return "ridge";
    case FeatureType::kValley:
      return "valley";
  }
  return "unknown";
}

void FeatureOptions::Check() const { CheckFields(*this); }

int FrameFeatures::Count(FeatureType type) const {
  return static_cast<int>(
      std::count_if(features.begin(), features.end(), [&](const Feature& f) { return f.type == type; }));
}

namespace {

using Vec3f = Eigen::Vector3f;

struct Candidate {
  int cell;
  Vec3f position;
  Vec3f direction;
  float salience;
  int32_t proxy;
};

// Well-spaced selection in two passes, both on a hash grid of `spacing`-sized voxels:
// first the most salient candidate of each voxel (ties: grid order), then those
// representatives in order of salience, each kept unless one already kept lies within
// `spacing`. Greedy over all candidates would give the same guarantee with ~30x more hash
// look-ups; the cost is a somewhat sparser sampling (gaps up to about 2 spacings).
std::vector<Candidate> SelectSpaced(const std::vector<Candidate>& candidates, double spacing) {
  if (spacing <= 0) {
    std::vector<Candidate> all = candidates;
    std::stable_sort(all.begin(), all.end(),
                     [](const Candidate& a, const Candidate& b) { return a.salience > b.salience; });
    return all;
  }
  auto voxel = [&](const Vec3f& p) {
    return Eigen::Vector3i(static_cast<int>(std::floor(p.x() / spacing)), static_cast<int>(std::floor(p.y() / spacing)),
                           static_cast<int>(std::floor(p.z() / spacing)));
  };
  // Voxel -> candidate index.
  CoordTable best(candidates.size());
  for (int i = 0; i < static_cast<int>(candidates.size()); ++i) {
    int& slot = best.At(PackCoords(voxel(candidates[i].position)));
    if (slot < 0 || candidates[i].salience > candidates[slot].salience) slot = i;
  }
  std::vector<int> order = best.Values();
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return candidates[a].salience != candidates[b].salience ? candidates[a].salience > candidates[b].salience : a < b;
  });
  CoordTable kept_at(order.size());  // voxel -> kept candidate (at most one per voxel)
  std::vector<Candidate> kept;
  const float s2 = static_cast<float>(spacing * spacing);
  for (int i : order) {
    const Candidate& c = candidates[i];
    const Eigen::Vector3i v = voxel(c.position);
    // Its own voxel first: where a kept neighbour is most often found.
    int k = kept_at.Find(PackCoords(v));
    bool near = k >= 0 && (candidates[k].position - c.position).squaredNorm() < s2;
    for (int dx = -1; dx <= 1 && !near; ++dx) {
      for (int dy = -1; dy <= 1 && !near; ++dy) {
        for (int dz = -1; dz <= 1 && !near; ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          k = kept_at.Find(PackCoords(v + Eigen::Vector3i(dx, dy, dz)));
          near = k >= 0 && (candidates[k].position - c.position).squaredNorm() < s2;
        }
      }
    }
    if (near) continue;
    kept_at.At(PackCoords(v)) = i;
    kept.push_back(c);
  }
  return kept;
}

// Principal direction of the same-type edge cells around `cell`, or zero if fewer than 3.
Vec3f EdgeDirection(const PointGrid& g, const std::vector<uint8_t>& is_type, int cell, int radius, float radius3d) {
  const int x0 = cell % g.width, y0 = cell / g.width;
  const Vec3f& c = g.points[cell];
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d sum2 = Eigen::Matrix3d::Zero();
  int n = 0;
  for (int y = std::max(0, y0 - radius); y <= std::min(g.height - 1, y0 + radius); ++y) {
    for (int x = std::max(0, x0 - radius); x <= std::min(g.width - 1, x0 + radius); ++x) {
      const int j = g.Index(x, y);
      if (!is_type[j]) continue;
      const Vec3f d = g.points[j] - c;
      if (d.squaredNorm() > radius3d * radius3d) continue;
      const Eigen::Vector3d dd = d.cast<double>();
      sum += dd;
      sum2 += dd * dd.transpose();
      ++n;
    }
  }
  if (n < 3) return Vec3f::Zero();
  const Eigen::Vector3d mean = sum / n;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(sum2 / n - mean * mean.transpose());
  Eigen::Vector3d axis = eig.eigenvectors().col(2);
  return axis.cast<float>().normalized();
}

// Lines are undirected: one canonical sign, so the same edge gives the same vector.
Vec3f Canonical(Vec3f d) {
  int k = 0;
  d.cwiseAbs().maxCoeff(&k);
  return d[k] < 0 ? Vec3f(-d) : d;
}

// The image tangent of a contour lifted to 3D at the cell's depth: the fallback direction
// when too few edge cells are around for a fit.
Vec3f TangentDirection(const PointGrid& g, const CameraIntrinsics& k, int cell, int jump_dx, int jump_dy) {
  const Vec3f& p = g.points[cell];
  const double u = g.PixelU(cell % g.width), v = g.PixelV(cell / g.width);
  const Eigen::Vector3d q = k.Unproject(u - jump_dy, v + jump_dx, p.z());
  return (q.cast<float>() - p).normalized();
}

}  // namespace

FrameFeatures ExtractFrameFeatures(const cv::Mat& depth, const CameraIntrinsics& k, const FeatureOptions& o,
                                   FeatureDebug* debug) {
  FrameFeatures out;
  PointGrid g = BuildPointGrid(depth, k, o.grid);
  const int n = g.width * g.height;
  if (g.ValidCount() == 0) {
    out.note = "no valid depth";
    if (debug) debug->grid = std::move(g), debug->labels.assign(n, -1);
    return out;
  }
  ProxySegmentation seg = ExtractProxies(g, o.proxies);
  out.proxies = seg.proxies;
  const std::vector<int32_t>& label = seg.labels;

  std::vector<Candidate> by_type[kFeatureTypeCount];
  // Planes.
  for (int i = 0; i < n; ++i) {
    if (!IsFlat(g, i, o.proxies)) continue;
    by_type[0].push_back({i, g.points[i], g.normals[i], Flatness(g, i, o.proxies), label[i]});
  }

  // Contours: a jump between a cell and the next valid cell to its right or below (across
  // at most edge_max_gap invalid cells).
  std::vector<float> jump_at(n, 0.0f);  // largest jump seen at a cell
  std::vector<int8_t> contour(n, 0);    // +1 silhouette (near side), -1 shadow (far side)
  std::vector<Eigen::Vector2i> jump_dir(n, Eigen::Vector2i::Zero());
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int i = g.Index(x, y);
      if (!g.Valid(i)) continue;
      const int dirs[2][2] = {{1, 0}, {0, 1}};
      for (const auto& d : dirs) {
        for (int step = 1; step <= o.edge_max_gap + 1; ++step) {
          const int xx = x + d[0] * step, yy = y + d[1] * step;
          if (xx >= g.width || yy >= g.height) break;
          const int j = g.Index(xx, yy);
          if (!g.Valid(j)) continue;
          const float zi = g.points[i].z(), zj = g.points[j].z();
          const float near = std::min(zi, zj), jump = std::abs(zi - zj);
          if (jump > o.edge_jump_fraction * near && jump >= o.edge_min_jump) {
            const int front = zi < zj ? i : j, back = zi < zj ? j : i;
            const int sign = zi < zj ? 1 : -1;  // direction from the near cell to the far one
            if (jump > jump_at[front]) {
              jump_at[front] = jump, contour[front] = 1, jump_dir[front] = {d[0] * sign, d[1] * sign};
            }
            if (jump > jump_at[back] && contour[back] != 1) {
              jump_at[back] = jump, contour[back] = -1, jump_dir[back] = {-d[0] * sign, -d[1] * sign};
            }
          }
          break;  // only the first valid cell counts
        }
      }
    }
  }
  std::vector<uint8_t> is_silhouette(n), is_shadow(n), is_border(n, 0);
  for (int i = 0; i < n; ++i) is_silhouette[i] = contour[i] == 1, is_shadow[i] = contour[i] == -1;
  if (o.border_features) {
    for (int y = 0; y < g.height; ++y) {
      for (int x = 0; x < g.width; ++x) {
        const int i = g.Index(x, y);
        if ((x == 0 || y == 0 || x == g.width - 1 || y == g.height - 1) && g.Valid(i) && contour[i] == 0)
          is_border[i] = 1;
      }
    }
  }
  const int r = o.edge_direction_radius;
  const float r3 = static_cast<float>(o.grid.normal_radius);
  for (int i = 0; i < n; ++i) {
    if (contour[i] != 0) {
      const std::vector<uint8_t>& same = contour[i] == 1 ? is_silhouette : is_shadow;
      Vec3f dir = EdgeDirection(g, same, i, r, r3);
      if (dir.isZero()) dir = TangentDirection(g, k, i, jump_dir[i].x(), jump_dir[i].y());
      const float salience = std::min(1.0f, jump_at[i] / 0.5f);
      by_type[contour[i] == 1 ? 1 : 2].push_back({i, g.points[i], Canonical(dir), salience, label[i]});
    } else if (is_border[i]) {
      Vec3f dir = EdgeDirection(g, is_border, i, r, r3);
      const int x = i % g.width;
      const bool vertical_side = x == 0 || x == g.width - 1;
      if (dir.isZero()) dir = TangentDirection(g, k, i, vertical_side ? 1 : 0, vertical_side ? 0 : 1);
      by_type[3].push_back({i, g.points[i], Canonical(dir), 1.0f, label[i]});
    }
  }

  // Creases: two proxies meeting (across at most crease_max_gap unlabelled, jump-free cells)
  // at more than crease_angle_deg. The feature sits on the planes' intersection line, at the
  // point nearest the two cells' midpoint.
  const float cos_crease = static_cast<float>(std::cos(o.crease_angle_deg * M_PI / 180));
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int i = g.Index(x, y);
      const int a = label[i];
      if (a < 0 || contour[i] != 0) continue;  // creases only between jump-free cells
      const int dirs[2][2] = {{1, 0}, {0, 1}};
      for (const auto& d : dirs) {
        int j = -1;
        for (int step = 1; step <= o.crease_max_gap + 1; ++step) {
          const int xx = x + d[0] * step, yy = y + d[1] * step;
          if (xx >= g.width || yy >= g.height) break;
          const int c = g.Index(xx, yy);
          if (!g.Valid(c) || contour[c] != 0) break;
          if (label[c] == a) break;
          if (label[c] >= 0) {
            j = c;
            break;
          }
        }
        if (j < 0) continue;
        const int b = label[j];
        const PlanarProxy& pa = out.proxies[a];
        const PlanarProxy& pb = out.proxies[b];
        const float cosine = pa.normal.dot(pb.normal);
        if (cosine > cos_crease) continue;
        const Vec3f line = pa.normal.cross(pb.normal);
        if (line.squaredNorm() < 1e-8f) continue;  // antiparallel: no line
        const Vec3f m = 0.5f * (g.points[i] + g.points[j]);
        Eigen::Matrix2f gram;
        gram << 1.0f, cosine, cosine, 1.0f;
        const Eigen::Vector2f rhs(pa.offset - pa.normal.dot(m), pb.offset - pb.normal.dot(m));
        const Eigen::Vector2f ab = gram.inverse() * rhs;
        const Vec3f on_line = m + ab.x() * pa.normal + ab.y() * pb.normal;
        // The planes must meet between the two cells, not beyond them (near a corner, where a
        // third surface takes over, the line of two planes runs on past the real edge).
        // And close by: two planes seen across a small undetected step also "meet" between
        // the cells, behind the nearer surface.
        const float span = (g.points[i] - g.points[j]).norm();
        if ((on_line - g.points[i]).norm() > span || (on_line - g.points[j]).norm() > span) continue;
        if ((on_line - m).norm() > o.proxies.max_distance) continue;
        // Concave (valley) when each plane's points lie in front of the other plane.
        const float side = pa.normal.dot(pb.centroid - on_line) + pb.normal.dot(pa.centroid - on_line);
        const float salience = line.norm();  // sin of the angle between the normals
        by_type[side > 0 ? 5 : 4].push_back({i, on_line, Canonical(line.normalized()), salience, a});
      }
    }
  }

  for (int t = 0; t < kFeatureTypeCount; ++t) {
    for (const Candidate& c : SelectSpaced(by_type[t], o.min_spacing)) {
      Feature f;
      f.type = static_cast<FeatureType>(t);
      f.position = c.position;
      f.direction = c.direction;
      f.salience = c.salience;
      f.proxy = c.proxy;
      f.pixel = {static_cast<float>(g.PixelU(c.cell % g.width)), static_cast<float>(g.PixelV(c.cell / g.width))};
      out.features.push_back(f);
    }
  }
  // Partial results say why (one note, the most telling).
  const int edges = out.Count(FeatureType::kSilhouette) + out.Count(FeatureType::kShadow) +
                    out.Count(FeatureType::kRidge) + out.Count(FeatureType::kValley);
  if (out.proxies.empty()) {
    out.note = "no planar region";
  } else if (edges == 0) {
    out.note = "no depth edges or creases";
  }
  if (debug) {
    debug->grid = std::move(g);
    debug->labels = label;
  }
  return out;
}

}  // namespace f2c
