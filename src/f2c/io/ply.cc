#include "f2c/io/ply.h"

#include <fmt/format.h>

#include <cstring>
#include <sstream>

#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {

void WritePly(const std::filesystem::path& path, const PlyPoints& p) {
  const size_t n = p.positions.size();
  if (!p.normals.empty() && p.normals.size() != n) ThrowInputError(path, "PLY: one normal per point needed");
  if (!p.colors.empty() && p.colors.size() != n) ThrowInputError(path, "PLY: one colour per point needed");
  std::string out = fmt::format("ply\nformat binary_little_endian 1.0\ncomment written by fine2coarse\n"
                                "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
                                n);
  if (!p.normals.empty()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!p.colors.empty()) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out += "end_header\n";
  const size_t record = 12 + (p.normals.empty() ? 0 : 12) + (p.colors.empty() ? 0 : 3);
  const size_t header = out.size();
  out.resize(header + n * record);
  char* at = out.data() + header;
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(at, p.positions[i].data(), 12), at += 12;
    if (!p.normals.empty()) std::memcpy(at, p.normals[i].data(), 12), at += 12;
    if (!p.colors.empty()) std::memcpy(at, p.colors[i].data(), 3), at += 3;
  }
  WriteFileAtomic(path, out);
}

PlyPoints ReadPly(const std::filesystem::path& path) {
  const std::string bytes = ReadFileToString(path);
  const size_t end = bytes.find("end_header\n");
  if (bytes.rfind("ply\n", 0) != 0 || end == std::string::npos) ThrowInputError(path, "not a PLY file");
  std::istringstream header(bytes.substr(0, end));
  std::string line;
  size_t n = 0;
  bool binary = false, normals = false, colors = false;
  while (std::getline(header, line)) {
    if (line == "format binary_little_endian 1.0") binary = true;
    if (line.rfind("element vertex ", 0) == 0) n = std::stoul(line.substr(15));
    if (line == "property float nx") normals = true;
    if (line == "property uchar red") colors = true;
  }
  if (!binary) ThrowInputError(path, "PLY: only binary little-endian point sets are read");
  const size_t record = 12 + (normals ? 12 : 0) + (colors ? 3 : 0);
  const size_t body = end + 11;
  if (bytes.size() != body + n * record) ThrowInputError(path, "PLY: file size does not match its header");
  PlyPoints p;
  p.positions.resize(n);
  if (normals) p.normals.resize(n);
  if (colors) p.colors.resize(n);
  const char* at = bytes.data() + body;
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(p.positions[i].data(), at, 12), at += 12;
    if (normals) std::memcpy(p.normals[i].data(), at, 12), at += 12;
    if (colors) std::memcpy(p.colors[i].data(), at, 3), at += 3;
  }
  return p;
}

}  // namespace f2c
