#pragma once
// The zero level set of a TSDF volume as a triangle mesh (marching cubes, Lorensen & Cline
// 1987), over the allocated blocks and across their borders.
//
// The case table is derived, not typed in: for each of the 256 sign patterns of a cell's
// corners, each face of the cube contributes the segments that separate its inside corners
// (tsdf < 0) from its outside ones, a face with two diagonal inside corners cutting each off
// on its own. Two cells that share a face derive the same segments on it, so the surface has
// no cracks; the segments join into closed loops, fanned into triangles whose normals point
// to the outside (free space, towards the cameras), and every edge of the mesh has one
// triangle on each side. See docs/fusion.md.

#include <array>
#include <cstdint>
#include <vector>

#include "f2c/fusion/tsdf.h"
#include "f2c/io/ply.h"
#include "f2c/util/fields.h"

namespace f2c {

// The loops of one sign pattern (bit i set: corner i inside), as cube edges in order.
// Corner i sits at offset (i & 1, i >> 1 & 1, i >> 2 & 1); edge 4 a + j runs along axis a
// from the corner with bit a clear, j packing the other two axes' bits in increasing axis order.
// A loop is fanned from its first vertex, or, where three or more of its vertices lie on one
// face of the cube (an ambiguous face whose two segments it both holds), around an extra
// vertex at its centre: a fan's diagonal could then lie in that face, and the neighbouring
// cell draw the same one (an edge of four triangles).
struct MarchingCubesLoop {
  std::vector<int8_t> edges;
  bool centre = false;
};
const std::vector<MarchingCubesLoop>& MarchingCubesLoops(int pattern);

// The loops' triangles, as triples of cube edges; kMarchingCubesCentre stands for a loop's
// centre vertex.
constexpr int8_t kMarchingCubesCentre = 12;
std::vector<std::array<int8_t, 3>> MarchingCubesCase(int pattern);

struct MeshOptions {
  // A cell is meshed only where all 8 corners were observed at least this often.
  float min_weight = 1.0f;

  template <class V>
  void Fields(V& v) {
    v.Group("Mesh (TSDF fusion, marching cubes; docs/fusion.md)");
    F2C_FIELD(v, min_weight, "--mesh-min-weight", Positive(), "mesh only where every voxel was seen this often");
  }
  void Check() const { CheckFields(*this); }
};

// Vertices (metres, world frame) with colours and normals (area-weighted face normals,
// pointing to free space), and triangles. Vertices are shared between cells and blocks; the
// order is canonical (by edge), so the mesh is the same for any thread count.
PlyPoints ExtractMesh(const TsdfVolume& volume, const MeshOptions& options = {});

}  // namespace f2c
