#pragma once
// PLY point sets and triangle meshes (binary little-endian, the format MeshLab, CloudCompare
// and Open3D read fastest): positions, optional normals, optional colours, optional
// triangles. Written atomically.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <vector>

namespace f2c {

struct PlyPoints {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;        // empty, or one per position
  std::vector<std::array<uint8_t, 3>> colors;  // empty, or one per position (RGB)
  std::vector<std::array<int32_t, 3>> faces;   // triangles (vertex indices); empty for points
};

// InputError naming the path when the sizes disagree, a face names a missing vertex, or the
// file cannot be written.
void WritePly(const std::filesystem::path& path, const PlyPoints& points);
// Reads what WritePly writes (binary little-endian float x y z [nx ny nz] [uchar r g b],
// then faces as "list uchar int vertex_indices" of 3); InputError naming the file when it
// is not such a file, is cut short or names a missing vertex.
PlyPoints ReadPly(const std::filesystem::path& path);

}  // namespace f2c
