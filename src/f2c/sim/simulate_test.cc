#include "f2c/sim/simulate.h"

#include <gtest/gtest.h>

#include "f2c/io/sequence.h"
#include "f2c/util/file.h"

namespace f2c::sim {
namespace {
namespace fs = std::filesystem;

fs::path Fresh(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("f2c_sim_" + name);
  fs::remove_all(dir);
  return dir;
}

SimulateOptions Small(int frames) {
  SimulateOptions o;
  o.scene = "two-rooms";
  o.seed = 5;
  o.walk.frames = frames;
  o.intrinsics = {262.5, 262.5, 159.5, 119.5, 320, 240};
  o.correspondences = 60;
  return o;
}

TEST(Simulate, WritesATumFolderTheReadersUnderstand) {
  const fs::path dir = Fresh("tum");
  SimulateOptions o = Small(6);
  o.intrinsics = {525.0, 525.0, 319.5, 239.5, 640, 480};
  const Trajectory poses = Simulate(dir, o, true);
  const RgbdSequence seq = ReadSequence(dir);
  EXPECT_EQ(seq.layout, DatasetLayout::kTum);
  ASSERT_EQ(seq.frames.size(), 6u);
  ASSERT_TRUE(seq.intrinsics.has_value());
  EXPECT_DOUBLE_EQ(seq.intrinsics->fx, 525.0);
  ASSERT_TRUE(seq.ground_truth.has_value());
  EXPECT_LT((seq.ground_truth->world_from_camera[3].matrix() - poses.world_from_camera[3].matrix()).norm(), 1e-6);
}

TEST(Simulate, SameSeedSameBytes) {
  const fs::path a = Fresh("bytes_a"), b = Fresh("bytes_b");
  Simulate(a, Small(3), true);
  Simulate(b, Small(3), true);
  for (const char* f : {"rgb.txt", "groundtruth.txt", "correspondences.txt"}) {
    EXPECT_EQ(ReadFileToString(a / f), ReadFileToString(b / f)) << f;
  }
  for (const auto& e : fs::directory_iterator(a / "depth")) {
    EXPECT_EQ(ReadFileToString(e.path()), ReadFileToString(b / "depth" / e.path().filename())) << e.path();
  }
}

TEST(Simulate, WalkMovesAboutOneMetrePerSecond) {
  const Scene scene = BuildScene("apartment", 0);
  WalkOptions w;
  w.frames = 301;
  const Trajectory t = GenerateWalk(scene, w);
  double path = 0;
  for (size_t i = 1; i < t.size(); ++i) {
    path += (t.world_from_camera[i].translation() - t.world_from_camera[i - 1].translation()).head<2>().norm();
  }
  EXPECT_NEAR(path, 10.0, 1.0);  // 10 s at 1 m/s (plus a little shake)
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t.world_from_camera[i].translation().z(), 1.5, 0.02);
  // Hand-held: no jumps. Body turns are rate-limited (60 deg/s) and the head sweep adds at
  // most 35 deg * 2 pi / 6 s = 37 deg/s: under 3.5 degrees per frame at 30 Hz.
  WalkOptions long_walk = w;
  long_walk.frames = 2400;  // the whole route and back
  const Trajectory lt = GenerateWalk(scene, long_walk);
  for (size_t i = 1; i < lt.size(); ++i) {
    const double angle =
        RotationAngle(lt.world_from_camera[i - 1].linear().transpose() * lt.world_from_camera[i].linear());
    ASSERT_LT(angle * 180 / M_PI, 3.5) << "frame " << i;
  }
}

TEST(Simulate, CorrespondencesMapToTheSameWorldPoint) {
  std::vector<Correspondence> cs;
  // 30 s walks (the demo's length) return to the first room in both scenes, so loop pairs
  // (more than 5 s apart) exist: about half of them.
  for (const std::string name : {"two-rooms", "apartment"}) {
    const Scene scene = BuildScene(name, 5);
    const Renderer renderer(scene);
    WalkOptions w;
    w.frames = 900;
    w.seed = 5;
    const Trajectory poses = GenerateWalk(scene, w);
    const CameraIntrinsics k{525.0, 525.0, 319.5, 239.5, 640, 480};
    cs = SampleCorrespondences(scene, renderer, k, poses, 100, 5);
    ASSERT_EQ(cs.size(), 100u) << name;
    int loops = 0;
    for (const Correspondence& c : cs) {
      const Eigen::Vector3d wa = poses.world_from_camera[c.frame_a] * c.point_in_a;
      const Eigen::Vector3d wb = poses.world_from_camera[c.frame_b] * c.point_in_b;
      EXPECT_LT((wa - wb).norm(), 1e-3) << name;
      loops += std::abs(c.frame_b - c.frame_a) > 150;
    }
    EXPECT_GE(loops, 40) << name;
  }
  const fs::path path = Fresh("corr") / "c.txt";
  fs::create_directories(path.parent_path());
  WriteCorrespondences(path, cs);
  const auto back = ReadCorrespondences(path);
  ASSERT_EQ(back.size(), cs.size());
  EXPECT_LT((back[7].point_in_b - cs[7].point_in_b).norm(), 1e-5);
}

}  // namespace
}  // namespace f2c::sim
