#include "f2c/fusion/marching_cubes.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

namespace f2c {
namespace {

Eigen::Vector3i CornerOffset(int i) { return {i & 1, i >> 1 & 1, i >> 2 & 1}; }

// The cube edge between corners i and j (one bit apart).
int EdgeOf(int i, int j) {
  const int axis = (i ^ j) == 1 ? 0 : (i ^ j) == 2 ? 1 : 2;
  const int lower = i & j;
  int packed = 0, bit = 0;
  for (int other = 0; other < 3; ++other) {
    if (other == axis) continue;
    packed |= (lower >> other & 1) << bit++;
  }
  return 4 * axis + packed;
}

int EdgeLowerCorner(int edge) {
  const int axis = edge / 4;
  int corner = 0, bit = 0;
  for (int other = 0; other < 3; ++other) {
    if (other == axis) continue;
    corner |= (edge % 4 >> bit++ & 1) << other;
  }
  return corner;
}

// The derivation described in the header. On each face, with its corners q0..q3 in
// counter-clockwise order seen from outside the cube and e_m the edge from q_m to q_m+1,
// every segment runs from an edge crossed inside-to-outside to one crossed
// outside-to-inside. A cube edge is walked one way by one of its faces and the other way by
// the other, so each crossed edge starts one segment and ends one: the segments close
// into loops.
std::vector<MarchingCubesLoop> DeriveLoops(int pattern) {
  auto inside = [&](int corner) { return (pattern >> corner & 1) != 0; };
  std::array<int, 12> next;
  next.fill(-1);
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      std::array<int, 4> q;
      const int order[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // counter-clockwise seen from +axis
      for (int m = 0; m < 4; ++m) q[m] = side << axis | order[m][0] << b | order[m][1] << c;
      if (side == 0) std::reverse(q.begin(), q.end());  // seen from -axis
      std::array<int, 4> e;
      for (int m = 0; m < 4; ++m) e[m] = EdgeOf(q[m], q[(m + 1) % 4]);
      int crossings = 0;
      for (int m = 0; m < 4; ++m) crossings += inside(q[m]) != inside(q[(m + 1) % 4]);
      if (crossings == 2) {
        int in_out = -1, out_in = -1;
        for (int m = 0; m < 4; ++m) {
          if (inside(q[m]) && !inside(q[(m + 1) % 4])) in_out = e[m];
          if (!inside(q[m]) && inside(q[(m + 1) % 4])) out_in = e[m];
        }
        next[in_out] = out_in;
      } else if (crossings == 4) {
        // Two diagonal inside corners: each is cut off on its own, from the edge after it
        // (inside to outside) to the edge before it.
        for (int m = 0; m < 4; ++m) {
          if (inside(q[m])) next[e[m]] = e[(m + 3) % 4];
        }
      }
    }
  }
  std::vector<MarchingCubesLoop> loops;
  std::array<bool, 12> done{};
  for (int start = 0; start < 12; ++start) {
    if (next[start] < 0 || done[start]) continue;
    MarchingCubesLoop loop;
    for (int edge = start; !done[edge]; edge = next[edge]) {
      done[edge] = true;
      loop.edges.push_back(static_cast<int8_t>(edge));
    }
    // A fan from one vertex draws diagonals between the loop's vertices; where three or more
    // of them lie on one face (both segments of an ambiguous face in one loop), a diagonal
    // can lie in that face, and the cell across it may draw the same one: an edge of four
    // triangles. Such a loop is fanned around its centre instead.
    for (int axis = 0; axis < 3 && !loop.centre; ++axis) {
      for (int side = 0; side < 2 && !loop.centre; ++side) {
        int on_face = 0;
        for (int8_t e : loop.edges) {
          const int lower = EdgeLowerCorner(e), upper = lower | 1 << (e / 4);
          on_face += (lower >> axis & 1) == side && (upper >> axis & 1) == side;
        }
        loop.centre = on_face >= 3;
      }
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Edge keys: the edge's lower voxel (20 bits per axis, two's complement) and its axis.
uint64_t EdgeKey(const Eigen::Vector3i& voxel, int axis) {
  const uint64_t packed = (static_cast<uint64_t>(static_cast<uint32_t>(voxel.x()) & 0xFFFFF) << 40) |
                          (static_cast<uint64_t>(static_cast<uint32_t>(voxel.y()) & 0xFFFFF) << 20) |
                          (static_cast<uint64_t>(static_cast<uint32_t>(voxel.z()) & 0xFFFFF));
  return packed << 2 | static_cast<uint64_t>(axis);
}

struct EdgeVertex {
  uint64_t key;
  Eigen::Vector3f position;
  std::array<uint8_t, 3> rgb;
};

struct BlockMesh {
  std::vector<EdgeVertex> vertices;
  std::vector<std::array<uint64_t, 3>> triangles;  // edge keys
};

}  // namespace

const std::vector<MarchingCubesLoop>& MarchingCubesLoops(int pattern) {
  static const std::vector<std::vector<MarchingCubesLoop>> loops = [] {
    std::vector<std::vector<MarchingCubesLoop>> all(256);
    for (int p = 0; p < 256; ++p) all[p] = DeriveLoops(p);
    return all;
  }();
  return loops[pattern & 255];
}

std::vector<std::array<int8_t, 3>> MarchingCubesCase(int pattern) {
  std::vector<std::array<int8_t, 3>> triangles;
  for (const MarchingCubesLoop& loop : MarchingCubesLoops(pattern)) {
    const std::vector<int8_t>& e = loop.edges;
    const size_t n = e.size();
    // Wound so that the normal points out of the inside (away from tsdf < 0).
    if (loop.centre) {
      for (size_t i = 0; i < n; ++i) triangles.push_back({kMarchingCubesCentre, e[(i + 1) % n], e[i]});
    } else {
      for (size_t i = 1; i + 1 < n; ++i) triangles.push_back({e[0], e[i + 1], e[i]});
    }
  }
  return triangles;
}

PlyPoints ExtractMesh(const TsdfVolume& volume, const MeshOptions& options) {
  const float voxel_size = static_cast<float>(volume.options().voxel_size);
  const int n = volume.BlockCount();
  std::vector<BlockMesh> parts(n);
  MarchingCubesLoops(0);  // derive the table before the threads start
  tbb::parallel_for(0, n, [&](int b) {
    BlockMesh& out = parts[b];
    const TsdfVoxel* own = volume.BlockVoxels(b);
    const Eigen::Vector3i origin = volume.BlockCoords(b) * kTsdfBlockSide;
    for (int z = 0; z < kTsdfBlockSide; ++z) {
      for (int y = 0; y < kTsdfBlockSide; ++y) {
        for (int x = 0; x < kTsdfBlockSide; ++x) {
          std::array<const TsdfVoxel*, 8> corner;
          bool complete = true;
          int pattern = 0;
          for (int i = 0; i < 8 && complete; ++i) {
            const Eigen::Vector3i o = CornerOffset(i) + Eigen::Vector3i(x, y, z);
            corner[i] = o.maxCoeff() < kTsdfBlockSide ? &own[(o.z() * kTsdfBlockSide + o.y()) * kTsdfBlockSide + o.x()]
                                                      : volume.Find(origin + o);
            complete = corner[i] != nullptr && corner[i]->weight >= options.min_weight;
            if (complete && corner[i]->tsdf < 0) pattern |= 1 << i;
          }
          if (!complete || pattern == 0 || pattern == 255) continue;
          const Eigen::Vector3i cell = origin + Eigen::Vector3i(x, y, z);
          auto vertex_on = [&](int edge) {
            const int axis = edge / 4, c0 = EdgeLowerCorner(edge), c1 = c0 | 1 << axis;
            const Eigen::Vector3i v0 = cell + CornerOffset(c0);
            const float d0 = corner[c0]->tsdf, d1 = corner[c1]->tsdf;
            const float s = d0 / (d0 - d1);  // where the distance crosses zero along the edge
            EdgeVertex vertex;
            vertex.key = EdgeKey(v0, axis);
            vertex.position = v0.cast<float>() * voxel_size;
            vertex.position[axis] += s * voxel_size;
            for (int ch = 0; ch < 3; ++ch) {
              vertex.rgb[ch] =
                  static_cast<uint8_t>(std::lround((1 - s) * corner[c0]->rgb[ch] + s * corner[c1]->rgb[ch]));
            }
            return vertex;
          };
          for (const MarchingCubesLoop& loop : MarchingCubesLoops(pattern)) {
            const size_t m = loop.edges.size();
            std::array<EdgeVertex, 12> ring;
            for (size_t i = 0; i < m; ++i) {
              ring[i] = vertex_on(loop.edges[i]);
              out.vertices.push_back(ring[i]);
            }
            if (loop.centre) {
              // The loop's mean, keyed by the cell (axis slot 3: no edge uses it).
              EdgeVertex centre;
              centre.key = EdgeKey(cell, 3);
              centre.position.setZero();
              Eigen::Vector3f rgb = Eigen::Vector3f::Zero();
              for (size_t i = 0; i < m; ++i) {
                centre.position += ring[i].position / static_cast<float>(m);
                rgb += Eigen::Vector3f(ring[i].rgb[0], ring[i].rgb[1], ring[i].rgb[2]) / static_cast<float>(m);
              }
              for (int ch = 0; ch < 3; ++ch) centre.rgb[ch] = static_cast<uint8_t>(std::lround(rgb[ch]));
              out.vertices.push_back(centre);
              for (size_t i = 0; i < m; ++i) out.triangles.push_back({centre.key, ring[(i + 1) % m].key, ring[i].key});
            } else {
              for (size_t i = 1; i + 1 < m; ++i) out.triangles.push_back({ring[0].key, ring[i + 1].key, ring[i].key});
            }
          }
        }
      }
    }
  });

  // One vertex per edge key (neighbouring cells and blocks computed it from the same two
  // voxels, so the copies are equal), in key order.
  std::vector<EdgeVertex> vertices;
  std::vector<std::array<uint64_t, 3>> triangles;
  for (BlockMesh& part : parts) {
    vertices.insert(vertices.end(), part.vertices.begin(), part.vertices.end());
    triangles.insert(triangles.end(), part.triangles.begin(), part.triangles.end());
    part = {};
  }
  std::sort(vertices.begin(), vertices.end(), [](const EdgeVertex& a, const EdgeVertex& b) { return a.key < b.key; });
  vertices.erase(std::unique(vertices.begin(), vertices.end(),
                             [](const EdgeVertex& a, const EdgeVertex& b) { return a.key == b.key; }),
                 vertices.end());
  PlyPoints mesh;
  mesh.positions.reserve(vertices.size());
  mesh.colors.reserve(vertices.size());
  for (const EdgeVertex& v : vertices) mesh.positions.push_back(v.position), mesh.colors.push_back(v.rgb);
  auto index_of = [&](uint64_t key) {
    return static_cast<int32_t>(std::lower_bound(vertices.begin(), vertices.end(), key,
                                                 [](const EdgeVertex& v, uint64_t k) { return v.key < k; }) -
                                vertices.begin());
  };
  mesh.normals.assign(vertices.size(), Eigen::Vector3f::Zero());
  for (const std::array<uint64_t, 3>& t : triangles) {
    const std::array<int32_t, 3> face{index_of(t[0]), index_of(t[1]), index_of(t[2])};
    const Eigen::Vector3f area =
        (mesh.positions[face[1]] - mesh.positions[face[0]]).cross(mesh.positions[face[2]] - mesh.positions[face[0]]);
    if (face[0] == face[1] || face[1] == face[2] || face[0] == face[2] || !(area.squaredNorm() > 0)) continue;
    mesh.faces.push_back(face);
    for (int32_t i : face) mesh.normals[i] += area;  // area-weighted (|area| is twice the area)
  }
  for (Eigen::Vector3f& normal : mesh.normals) {
    if (normal.squaredNorm() > 0) normal.normalize();
  }
  return mesh;
}

}  // namespace f2c
