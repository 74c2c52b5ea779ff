#include "f2c/fusion/marching_cubes.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <map>
#include <random>
#include <set>
#include <utility>

namespace f2c {
namespace {

// Directed edge counts of a mesh: on a closed, consistently oriented surface every edge a->b
// is matched by b->a as often (a crack leaves an edge unmatched; a flipped triangle, one
// matched by itself).
std::map<std::pair<int, int>, int> DirectedEdges(const PlyPoints& mesh) {
  std::map<std::pair<int, int>, int> edges;
  for (const auto& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) ++edges[{f[k], f[(k + 1) % 3]}];
  }
  return edges;
}

TEST(MarchingCubesCase, EveryPatternUsesExactlyItsCrossingEdges) {
  for (int pattern = 0; pattern < 256; ++pattern) {
    std::set<int> crossing, used;
    for (int a = 0; a < 8; ++a) {
      for (int axis = 0; axis < 3; ++axis) {
        const int b = a | 1 << axis;
        if (b == a || ((pattern >> a & 1) == (pattern >> b & 1))) continue;
        // Edge 4 axis + j, j packing the other two axes' bits of the lower corner.
        int j = 0, bit = 0;
        for (int other = 0; other < 3; ++other) {
          if (other != axis) j |= (a >> other & 1) << bit++;
        }
        crossing.insert(4 * axis + j);
      }
    }
    for (const auto& t : MarchingCubesCase(pattern)) {
      for (int8_t e : t) {
        if (e != kMarchingCubesCentre) used.insert(e);
      }
    }
    EXPECT_EQ(used, crossing) << "pattern " << pattern;
  }
  EXPECT_TRUE(MarchingCubesCase(0).empty());
  EXPECT_TRUE(MarchingCubesCase(255).empty());
  EXPECT_EQ(MarchingCubesCase(1).size(), 1u);  // one corner cut off: one triangle
}

TsdfVolume Sphere(double radius, double voxel, const Eigen::Vector3d& centre) {
  TsdfOptions o;
  o.voxel_size = voxel;
  TsdfVolume volume(o);
  const int extent = static_cast<int>(std::ceil((radius + 6 * voxel) / voxel)) + 1;
  const Eigen::Vector3i c = (centre / voxel).array().round().cast<int>();
  for (int z = -extent; z <= extent; ++z) {
    for (int y = -extent; y <= extent; ++y) {
      for (int x = -extent; x <= extent; ++x) {
        const Eigen::Vector3i v = c + Eigen::Vector3i(x, y, z);
        const double sdf = (v.cast<double>() * voxel - centre).norm() - radius;
        if (std::abs(sdf) > 5 * voxel) continue;
        TsdfVoxel& t = volume.At(v);
        t.tsdf = static_cast<float>(std::clamp(sdf / o.Truncation(), -1.0, 1.0));
        t.weight = 1;
        t.rgb = {200, 100, 50};
      }
    }
  }
  return volume;
}

TEST(ExtractMesh, SphereIsClosedOnTheSurfaceAndFacesOutward) {
  const double radius = 0.23, voxel = 0.01;
  const Eigen::Vector3d centre(0.1234, -0.0567, 0.731);  // off the grid and across blocks
  const PlyPoints mesh = ExtractMesh(Sphere(radius, voxel, centre));
  ASSERT_GT(mesh.faces.size(), 1000u);
  const auto edges = DirectedEdges(mesh);
  for (const auto& [edge, count] : edges) {  // every edge in two faces, once each way
    ASSERT_EQ(count, 1) << edge.first << "->" << edge.second;
    ASSERT_EQ(edges.count({edge.second, edge.first}), 1u) << "crack at " << edge.first << "-" << edge.second;
  }
  double worst = 0;
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3d p = mesh.positions[i].cast<double>();
    worst = std::max(worst, std::abs((p - centre).norm() - radius));
    EXPECT_GT(mesh.normals[i].cast<double>().dot((p - centre).normalized()), 0.95) << "vertex " << i;
    EXPECT_EQ(mesh.colors[i], (std::array<uint8_t, 3>{200, 100, 50}));
  }
  EXPECT_LT(worst, 0.1 * voxel);
  // Faces wound outward: the signed volume is the sphere's.
  double volume = 0;
  for (const auto& f : mesh.faces) {
    volume += (mesh.positions[f[0]] - centre.cast<float>())
                  .cast<double>()
                  .dot((mesh.positions[f[1]] - centre.cast<float>())
                           .cast<double>()
                           .cross((mesh.positions[f[2]] - centre.cast<float>()).cast<double>())) /
              6;
  }
  EXPECT_NEAR(volume, 4.0 / 3.0 * M_PI * radius * radius * radius, 0.01 * volume);
}

TEST(ExtractMesh, RandomFieldIsAClosedManifoldWithoutFlips) {
  // Every sign pattern, ambiguous faces included, on a 16^3 grid (two blocks a side) whose
  // outer layer is outside, so every surface closes.
  TsdfVolume volume(TsdfOptions{});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(0.05f, 0.9f);
  for (int z = 0; z < 16; ++z) {
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 16; ++x) {
        const bool border = std::min({x, y, z}) == 0 || std::max({x, y, z}) == 15;
        TsdfVoxel& t = volume.At({x, y, z});
        t.tsdf = border || rng() % 2 ? value(rng) : -value(rng);
        t.weight = 1;
      }
    }
  }
  const PlyPoints mesh = ExtractMesh(volume);
  ASSERT_GT(mesh.faces.size(), 2000u);
  // Every edge in exactly two triangles, once each way: no crack, no flip, and no edge of
  // four triangles where two cells' fans could meet in an ambiguous face.
  const auto edges = DirectedEdges(mesh);
  for (const auto& [edge, count] : edges) {
    ASSERT_EQ(count, 1) << edge.first << "->" << edge.second;
    const auto reverse = edges.find({edge.second, edge.first});
    ASSERT_TRUE(reverse != edges.end() && reverse->second == 1) << edge.first << "-" << edge.second;
  }
  int centred = 0;
  for (int p = 0; p < 256; ++p) {
    for (const MarchingCubesLoop& loop : MarchingCubesLoops(p)) centred += loop.centre;
  }
  EXPECT_GT(centred, 0);  // the ambiguous patterns that need it
}

TEST(ExtractMesh, SameMeshForAnyThreadCount) {
  const TsdfVolume volume = Sphere(0.31, 0.01, {0.02, 0.5, -0.3});
  PlyPoints one;
  {
    tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    one = ExtractMesh(volume);
  }
  const PlyPoints many = ExtractMesh(volume);
  EXPECT_EQ(one.positions, many.positions);
  EXPECT_EQ(one.normals, many.normals);
  EXPECT_EQ(one.faces, many.faces);
}

TEST(ExtractMesh, UnobservedCornersGiveNoSurface) {
  TsdfVolume volume = Sphere(0.2, 0.01, {0, 0, 0});
  for (int b = 0; b < volume.BlockCount(); ++b) {
    if (volume.BlockCoords(b).x() < 0) continue;
    for (int i = 0; i < kTsdfBlockVoxels; ++i) {
      volume
          .At(volume.BlockCoords(b) * kTsdfBlockSide +
              Eigen::Vector3i(i % kTsdfBlockSide, i / kTsdfBlockSide % kTsdfBlockSide, i / 64))
          .weight = 0;
    }
  }
  const PlyPoints mesh = ExtractMesh(volume);
  ASSERT_FALSE(mesh.faces.empty());
  for (const auto& f : mesh.faces) {
    for (int32_t i : f) EXPECT_LT(mesh.positions[i].x(), 0.0f);  // only the observed half
  }
}

}  // namespace
}  // namespace f2c
