#include "f2c/io/ply.h"

#include <gtest/gtest.h>

#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

TEST(Ply, RoundTripsPointsNormalsAndColours) {
  const auto dir = testing::FreshTempDir("ply");
  PlyPoints p;
  for (int i = 0; i < 5; ++i) {
    p.positions.emplace_back(0.5f * i, -1.25f, 3.0f + i);
    p.normals.emplace_back(0.0f, i % 2 ? 1.0f : -1.0f, 0.0f);
    p.colors.push_back({static_cast<uint8_t>(50 * i), 7, 255});
  }
  WritePly(dir / "a.ply", p);
  const PlyPoints q = ReadPly(dir / "a.ply");
  EXPECT_EQ(q.positions, p.positions);
  EXPECT_EQ(q.normals, p.normals);
  EXPECT_EQ(q.colors, p.colors);
  // The header says what follows: 5 vertices of 27 bytes.
  const std::string bytes = ReadFileToString(dir / "a.ply");
  EXPECT_NE(bytes.find("element vertex 5\n"), std::string::npos);
  EXPECT_EQ(bytes.size() - (bytes.find("end_header\n") + 11), 5u * 27u);

  PlyPoints bad = p;
  bad.colors.pop_back();
  EXPECT_EQ(testing::InputErrorMessage([&] { WritePly(dir / "b.ply", bad); }),
            (dir / "b.ply").string() + ": PLY: one colour per point needed");
  EXPECT_FALSE(std::filesystem::exists(dir / "b.ply"));
}

TEST(Ply, RoundTripsTrianglesAndRejectsACutFile) {
  const auto dir = testing::FreshTempDir("ply_mesh");
  PlyPoints m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.colors = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}, {{10, 11, 12}}};
  m.faces = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  WritePly(dir / "m.ply", m);
  const PlyPoints q = ReadPly(dir / "m.ply");
  EXPECT_EQ(q.positions, m.positions);
  EXPECT_EQ(q.colors, m.colors);
  EXPECT_EQ(q.faces, m.faces);
  const std::string bytes = ReadFileToString(dir / "m.ply");
  EXPECT_NE(bytes.find("element face 4\nproperty list uchar int vertex_indices\n"), std::string::npos);
  // 4 vertices of 15 bytes, 4 faces of 13.
  EXPECT_EQ(bytes.size() - (bytes.find("end_header\n") + 11), 4u * 15u + 4u * 13u);

  WriteFileAtomic(dir / "cut.ply", bytes.substr(0, bytes.size() - 5));
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadPly(dir / "cut.ply"); }),
            (dir / "cut.ply").string() + ": PLY: file size does not match its header (cut short?)");
  PlyPoints bad = m;
  bad.faces.push_back({0, 1, 4});
  EXPECT_EQ(testing::InputErrorMessage([&] { WritePly(dir / "bad.ply", bad); }),
            (dir / "bad.ply").string() + ": PLY: a face names vertex 4 of 4");
  // A vertex that is not finite, or farther than any scan reaches, is an error naming it (a
  // NaN vertex in true surfaces made every distance NaN).
  PlyPoints nan = m;
  nan.positions[2].y() = std::nanf("");
  WritePly(dir / "nan.ply", nan);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadPly(dir / "nan.ply"); }),
            (dir / "nan.ply").string() + ": PLY: vertex 2 is not finite");
  PlyPoints far = m;
  far.positions[3].z() = 1e30f;
  WritePly(dir / "far.ply", far);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadPly(dir / "far.ply"); }),
            (dir / "far.ply").string() + ": PLY: vertex 3 lies 1e+30 m from the origin (at most 1e+06 m)");
}

}  // namespace
}  // namespace f2c
