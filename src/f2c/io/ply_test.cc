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

}  // namespace
}  // namespace f2c
