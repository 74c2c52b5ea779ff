#include "f2c/io/trajectory.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <functional>

#include "f2c/io/conf.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

Trajectory Example() {
  Trajectory t;
  for (int i = 0; i < 3; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(i, -0.5 * i, 0.25);
    t.Add(100.0 + i / 30.0, pose);
  }
  return t;
}

void ExpectSamePoses(const Trajectory& a, const Trajectory& b, double tolerance) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_LT((a.world_from_camera[i].matrix() - b.world_from_camera[i].matrix()).norm(), tolerance);
  }
}

TEST(TumTrajectory, RoundTrip) {
  const fs::path path = testing::FreshTempDir("traj_tum") / "t.txt";
  WriteTumTrajectory(path, Example());
  const Trajectory back = ReadTumTrajectory(path);
  ExpectSamePoses(back, Example(), 1e-8);
  EXPECT_NEAR(back.timestamps[1], 100.0 + 1 / 30.0, 1e-6);
}

TEST(TumTrajectory, MalformedLines) {
  const fs::path path = testing::FreshTempDir("traj_tum_bad") / "groundtruth.txt";
  WriteFileAtomic(path, "# header\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadTumTrajectory(path); }),
            path.string() + ":3: expected 'timestamp tx ty tz qx qy qz qw', got 7 fields");
  WriteFileAtomic(path, "1.0 0 0 nan 0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadTumTrajectory(path); }),
            path.string() + ":1: 'nan' is not a finite number; expected 'timestamp tx ty tz qx qy qz qw'");
  WriteFileAtomic(path, "1.0 0 0 0 0 0 0.5 0.5\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadTumTrajectory(path); }),
            path.string() + ":1: quaternion is not unit (norm 0.7071)");
  WriteFileAtomic(path, "# nothing\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadTumTrajectory(path); }), path.string() + ": trajectory holds no pose");
}

TEST(LogTrajectory, RoundTripKeepsFrameIds) {
  const fs::path path = testing::FreshTempDir("traj_log") / "t.log";
  WriteLogTrajectory(path, Example());
  const Trajectory back = ReadLogTrajectory(path);
  ExpectSamePoses(back, Example(), 1e-10);
  EXPECT_FALSE(back.has_timestamps);
  EXPECT_EQ(back.timestamps[2], 2.0);
}

TEST(LogTrajectory, MalformedBlocks) {
  const fs::path path = testing::FreshTempDir("traj_log_bad") / "t.log";
  WriteFileAtomic(path, "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
            path.string() + ": expected blocks of 5 lines ('i j n' and a 4x4 matrix), got 4 lines");
  WriteFileAtomic(path, "0 0 1\n1 0 0 0\n0 1 0 0\n0 0 1\n0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
            path.string() + ":4: expected a matrix row of 4 numbers, got 3 fields");
  WriteFileAtomic(path, "0 x 1\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
            path.string() + ":1: expected a block header 'i j n' of three integers");
  WriteFileAtomic(path, "0 0 1\n2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
            path.string() + ":2: pose is not rigid (max |R^T R - I| = 3, det R = 2)");
}

// One block per frame, ids in order: a repeated id (a pasted block, or 3DMatch's gt.log of
// frame pairs) and a gap (a frame without its pose) would place poses on the wrong frames.
TEST(LogTrajectory, RepeatedMissingAndNegativeFrameIds) {
  const fs::path path = testing::FreshTempDir("traj_log_ids") / "t.log";
  const std::string identity = "1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n";
  WriteFileAtomic(path, "4 4 5\n" + identity + "5 5 6\n" + identity);
  EXPECT_EQ(ReadLogTrajectory(path).timestamps, (std::vector<double>{4, 5}));
  WriteFileAtomic(path, "0 0 1\n" + identity + "1 1 2\n" + identity + "1 1 2\n" + identity);
  EXPECT_EQ(
      testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
      path.string() +
          ":11: frame id 1 after 1 (one block per frame, ids in order; a file of frame pairs is not a trajectory)");
  WriteFileAtomic(path, "0 1 3\n" + identity + "0 2 3\n" + identity);
  EXPECT_EQ(
      testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
      path.string() +
          ":6: frame id 0 after 0 (one block per frame, ids in order; a file of frame pairs is not a trajectory)");
  WriteFileAtomic(path, "0 0 1\n" + identity + "2 2 3\n" + identity);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
            path.string() + ":6: frame id 2 after 0: frame 1 has no pose");
  WriteFileAtomic(path, "-1 -1 0\n" + identity);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadLogTrajectory(path); }),
            path.string() + ":1: frame id -1 is negative");
}

// Poses for frames: by time stamp (any order in the file, within 1 ms, else interpolated
// between two close poses), by frame id for a .log, by image name for a .conf; the first
// frame without a pose is named.
TEST(PosesForFrames, ByTimeStampFrameIdOrName) {
  const Trajectory t = Example();  // 100, 100.0333, 100.0667 s
  Trajectory shuffled;
  for (int i : {2, 0, 1}) shuffled.Add(t.timestamps[i], t.world_from_camera[i]);
  const fs::path path = "poses.txt";
  const std::vector<std::string> names = {"a.png", "b.png", "c.png"};
  const auto poses = PosesForFrames(shuffled, {100.0 + 2 / 30.0 + 4e-4, 100.0, 100.0 + 1 / 30.0 - 9e-4}, names, path);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_TRUE(poses[0].isApprox(t.world_from_camera[2]));
  EXPECT_TRUE(poses[1].isApprox(t.world_from_camera[0]));
  EXPECT_TRUE(poses[2].isApprox(t.world_from_camera[1]));
  // Between two poses: interpolated, halfway at the midpoint (Example turns 0.3 rad and
  // moves (1, -0.5, 0) per pose about one axis).
  const auto mid = PosesForFrames(shuffled, {100.05}, {"a.png"}, path);
  EXPECT_LT((mid[0].translation() - Eigen::Vector3d(1.5, -0.75, 0.25)).norm(), 1e-9);
  EXPECT_TRUE(mid[0].linear().isApprox(
      Eigen::AngleAxisd(0.45, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(), 1e-9));
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(shuffled, {100.0, 100.2}, {"a.png", "b.png"}, path);
            }),
            "poses.txt: no pose within 1 ms of frame 1 (time stamp 100.200000 s), nor two within 0.25 s around it");
  EXPECT_EQ(testing::InputErrorMessage([&] { PosesForFrames(shuffled, {100.05}, {"a.png"}, path, 1e-3, 0.02); }),
            "poses.txt: no pose within 1 ms of frame 0 (time stamp 100.050000 s), nor two within 0.02 s around it");

  // A .log: frame ids, whatever the order of the blocks.
  Trajectory log;
  log.has_timestamps = false;
  for (int i : {2, 0, 1}) log.Add(i, t.world_from_camera[i]);
  const auto by_id = PosesForFrames(log, {7.0, 8.0, 9.0}, names, "t.log");
  ASSERT_EQ(by_id.size(), 3u);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(by_id[i].isApprox(t.world_from_camera[i])) << i;
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(log, {7.0, 8.0}, {"a.png", "b.png"}, "t.log");
            }),
            "t.log: frame id 2 but the dataset has 2 frames");
  log.timestamps = {1, 2, 3};
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(log, {7.0, 8.0, 9.0, 10.0}, {"a", "b", "c", "d"}, "t.log");
            }),
            "t.log: no pose for frame 0 ('a')");

  // A .conf: by image name, so permuted scan lines mean the same.
  Trajectory conf;
  conf.has_timestamps = false;
  for (int i : {2, 0, 1}) conf.Add(conf.size(), t.world_from_camera[i]), conf.frame_names.push_back(names[i]);
  const auto by_name = PosesForFrames(conf, {7.0, 8.0, 9.0}, names, "s.conf");
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(by_name[i].isApprox(t.world_from_camera[i])) << i;
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(conf, {7.0, 8.0, 9.0}, {"x", "y", "z"}, "s.conf");
            }),
            "s.conf: none of its 3 poses names a frame of the dataset (its first: 'c.png', the dataset's first: 'x')");
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(conf, {7.0, 8.0, 9.0, 10.0}, {"a.png", "b.png", "c.png", "d.png"}, "s.conf");
            }),
            "s.conf: no pose for frame 3 ('d.png')");
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(conf, {7.0, 8.0}, {"a.png", "a.png"}, "s.conf");
            }),
            "s.conf: its poses name their frames, but frames 0 and 1 of the dataset are both named 'a.png'");
  // Poses of frames the dataset (or its selection) does not hold are left out.
  EXPECT_EQ(FramesOfPoses(conf, {"b.png", "c.png"}, "s.conf"), (std::vector<long>{1, -1, 0}));
}

TEST(Conf, RoundTripThroughASequence) {
  const fs::path dir = testing::FreshTempDir("conf_rt");
  fs::create_directories(dir / "depth");
  fs::create_directories(dir / "color");
  RgbdSequence seq;
  seq.intrinsics = CameraIntrinsics{500, 500, 320, 240, 640, 480};
  seq.depth_scale = 1.0 / 5000.0;
  for (int i = 0; i < 3; ++i) {
    RgbdFrame f;
    f.timestamp = i;
    f.depth_path = dir / "depth" / fmt::format("1305031102.{}.png", i);  // dots in names
    f.color_path = dir / "color" / fmt::format("1305031102.{}.jpg", i);
    seq.frames.push_back(f);
  }
  WriteConf(dir / "scan.conf", seq, Example());
  const ConfFile conf = ReadConf(dir / "scan.conf");
  ExpectSamePoses(conf.trajectory, Example(), 1e-10);
  ASSERT_EQ(conf.sequence.frames.size(), 3u);
  EXPECT_EQ(conf.sequence.frames[1].depth_path, dir / "depth" / "1305031102.1.png");
  EXPECT_EQ(conf.sequence.frames[2].color_path, dir / "color" / "1305031102.2.jpg");
  EXPECT_DOUBLE_EQ(conf.sequence.depth_scale, 1.0 / 5000.0);
  EXPECT_DOUBLE_EQ(conf.sequence.intrinsics->fx, 500);
}

TEST(Conf, MalformedLines) {
  const fs::path path = testing::FreshTempDir("conf_bad") / "a.conf";
  WriteFileAtomic(path, "dataset tum\nn_image 3\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() +
                ":2: unknown key 'n_image' (expected dataset, intrinsics, intrinsics_matrix, "
                "n_images, depth_directory, image_directory or scan)");
  WriteFileAtomic(path, "dataset tum\nscan a.png b.jpg 1 0 0 0 0 1 0 0 0 0 1 0\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() + ":2: 'scan' expects '<depth> <colour>' and 16 numbers, got 14 fields");
  WriteFileAtomic(path, "dataset tum\nn_images 2\nscan a.png b.jpg 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() + ": n_images says 2 but 1 scan lines follow");
  WriteFileAtomic(path,
                  "dataset tum\nscan a.png b.jpg 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
                  "scan a.png c.jpg 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() + ":3: scan line names depth image 'a.png' again (line 2)");
  WriteFileAtomic(path, "dataset tum\nintrinsics_matrix 0 0 320 0 500 240 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() + ":2: focal length must be positive (fx=0, fy=500)");
}

// The dataset key selects how depth is decoded: any case, and an unknown name is an error
// (a guess reads TUM's 1/5000 m depth as millimetres, 5x too far).
TEST(Conf, DatasetNameInAnyCaseOrAnError) {
  const fs::path path = testing::FreshTempDir("conf_dataset") / "a.conf";
  const std::string scan = "scan a.png b.jpg 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n";
  WriteFileAtomic(path, "dataset TUM\n" + scan);
  EXPECT_DOUBLE_EQ(ReadConf(path).sequence.depth_scale, 1.0 / 5000.0);
  WriteFileAtomic(path, "dataset Redwood\n" + scan);
  EXPECT_DOUBLE_EQ(ReadConf(path).sequence.depth_scale, 0.001);
  EXPECT_EQ(ReadConf(path).trajectory.frame_names, (std::vector<std::string>{"a.png"}));
  WriteFileAtomic(path, "dataset scannet\n" + scan);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() +
                ":1: unknown dataset 'scannet' (expected tum, sun3d, 7scenes, 3dmatch or redwood: it selects how "
                "depth is decoded)");
}

}  // namespace
}  // namespace f2c
