#include "f2c/io/ply.h"

#include <fmt/format.h>

#include <cstring>
#include <sstream>

#include "f2c/geometry/rigid.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
constexpr size_t kFaceRecord = 13;  // uchar count (3), then three int32 indices
}  // namespace

void WritePly(const std::filesystem::path& path, const PlyPoints& p) {
  const size_t n = p.positions.size();
  if (!p.normals.empty() && p.normals.size() != n) ThrowInputError(path, "PLY: one normal per point needed");
  if (!p.colors.empty() && p.colors.size() != n) ThrowInputError(path, "PLY: one colour per point needed");
  for (const std::array<int32_t, 3>& f : p.faces) {
    for (int32_t i : f) {
      if (i < 0 || static_cast<size_t>(i) >= n)
        ThrowInputError(path, fmt::format("PLY: a face names vertex {} of {}", i, n));
    }
  }
  std::string out = fmt::format(
      "ply\nformat binary_little_endian 1.0\ncomment written by fine2coarse\n"
      "element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
      n);
  if (!p.normals.empty()) out += "property float nx\nproperty float ny\nproperty float nz\n";
  if (!p.colors.empty()) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (!p.faces.empty()) out += fmt::format("element face {}\nproperty list uchar int vertex_indices\n", p.faces.size());
  out += "end_header\n";
  const size_t record = 12 + (p.normals.empty() ? 0 : 12) + (p.colors.empty() ? 0 : 3);
  const size_t header = out.size();
  out.resize(header + n * record + p.faces.size() * kFaceRecord);
  char* at = out.data() + header;
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(at, p.positions[i].data(), 12), at += 12;
    if (!p.normals.empty()) std::memcpy(at, p.normals[i].data(), 12), at += 12;
    if (!p.colors.empty()) std::memcpy(at, p.colors[i].data(), 3), at += 3;
  }
  for (const std::array<int32_t, 3>& f : p.faces) {
    *at++ = 3;
    std::memcpy(at, f.data(), 12), at += 12;
  }
  WriteFileAtomic(path, out);
}

PlyPoints ReadPly(const std::filesystem::path& path) {
  const std::string bytes = ReadFileToString(path);
  const size_t end = bytes.find("end_header\n");
  if (bytes.rfind("ply\n", 0) != 0 || end == std::string::npos) ThrowInputError(path, "not a PLY file");
  std::istringstream header(bytes.substr(0, end));
  std::string line;
  size_t n = 0, faces = 0;
  bool binary = false, normals = false, colors = false;
  auto count = [&](const std::string& text) {
    size_t value = 0;
    try {
      value = std::stoul(text);
    } catch (const std::exception&) {
      ThrowInputError(path, "PLY: bad element count '" + text + "'");
    }
    return value;
  };
  while (std::getline(header, line)) {
    if (line == "format binary_little_endian 1.0") binary = true;
    if (line.rfind("element vertex ", 0) == 0) n = count(line.substr(15));
    if (line.rfind("element face ", 0) == 0) faces = count(line.substr(13));
    if (line == "property float nx") normals = true;
    if (line == "property uchar red") colors = true;
  }
  if (!binary) ThrowInputError(path, "PLY: only binary little-endian point sets are read");
  const size_t record = 12 + (normals ? 12 : 0) + (colors ? 3 : 0);
  const size_t body = end + 11;
  if (n > bytes.size() || faces > bytes.size() || bytes.size() != body + n * record + faces * kFaceRecord) {
    ThrowInputError(path, "PLY: file size does not match its header (cut short?)");
  }
  PlyPoints p;
  p.positions.resize(n);
  if (normals) p.normals.resize(n);
  if (colors) p.colors.resize(n);
  const char* at = bytes.data() + body;
  for (size_t i = 0; i < n; ++i) {
    std::memcpy(p.positions[i].data(), at, 12), at += 12;
    if (!p.positions[i].allFinite()) ThrowInputError(path, fmt::format("PLY: vertex {} is not finite", i));
    if (p.positions[i].cast<double>().norm() > kMaxCoordinateMetres) {
      ThrowInputError(path, fmt::format("PLY: vertex {} lies {:.3g} m from the origin (at most {:g} m)", i,
                                        p.positions[i].cast<double>().norm(), kMaxCoordinateMetres));
    }
    if (normals) std::memcpy(p.normals[i].data(), at, 12), at += 12;
    if (colors) std::memcpy(p.colors[i].data(), at, 3), at += 3;
  }
  p.faces.resize(faces);
  for (std::array<int32_t, 3>& f : p.faces) {
    if (*at != 3) ThrowInputError(path, "PLY: only triangles are read");
    std::memcpy(f.data(), at + 1, 12), at += kFaceRecord;
    for (int32_t i : f) {
      if (i < 0 || static_cast<size_t>(i) >= n)
        ThrowInputError(path, fmt::format("PLY: a face names vertex {} of {}", i, n));
    }
  }
  return p;
}

}  // namespace f2c
