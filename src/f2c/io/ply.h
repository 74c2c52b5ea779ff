#pragma once
// PLY point sets (binary little-endian, the format MeshLab, CloudCompare and Open3D read
// fastest): positions, optional normals, optional colours. Written atomically.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <vector>

namespace f2c {

struct PlyPoints {
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;               // empty, or one per position
  std::vector<std::array<uint8_t, 3>> colors;         // empty, or one per position (RGB)
};

// InputError naming the path when the sizes disagree or the file cannot be written.
void WritePly(const std::filesystem::path& path, const PlyPoints& points);
// Reads what WritePly writes (binary little-endian float x y z [nx ny nz] [uchar r g b]).
PlyPoints ReadPly(const std::filesystem::path& path);

}  // namespace f2c
