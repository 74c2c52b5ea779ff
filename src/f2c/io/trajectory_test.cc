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

// Poses for frames: by time stamp (any order in the file, within 1 ms, else interpolated
// between two close poses), or in order for a file without time stamps; the first frame
// without a pose is named.
TEST(PosesForFrames, ByTimeStampOrInOrder) {
  const Trajectory t = Example();  // 100, 100.0333, 100.0667 s
  Trajectory shuffled;
  for (int i : {2, 0, 1}) shuffled.Add(t.timestamps[i], t.world_from_camera[i]);
  const fs::path path = "poses.txt";
  const auto poses = PosesForFrames(shuffled, {100.0 + 2 / 30.0 + 4e-4, 100.0, 100.0 + 1 / 30.0 - 9e-4}, path);
  ASSERT_EQ(poses.size(), 3u);
  EXPECT_TRUE(poses[0].isApprox(t.world_from_camera[2]));
  EXPECT_TRUE(poses[1].isApprox(t.world_from_camera[0]));
  EXPECT_TRUE(poses[2].isApprox(t.world_from_camera[1]));
  // Between two poses: interpolated, halfway at the midpoint (Example turns 0.3 rad and
  // moves (1, -0.5, 0) per pose about one axis).
  const auto mid = PosesForFrames(shuffled, {100.05}, path);
  EXPECT_LT((mid[0].translation() - Eigen::Vector3d(1.5, -0.75, 0.25)).norm(), 1e-9);
  EXPECT_TRUE(mid[0].linear().isApprox(
      Eigen::AngleAxisd(0.45, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(), 1e-9));
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(shuffled, {100.0, 100.2}, path);
            }),
            "poses.txt: no pose within 1 ms of frame 1 (time stamp 100.200000 s), nor two within 0.25 s around it");
  EXPECT_EQ(testing::InputErrorMessage([&] { PosesForFrames(shuffled, {100.05}, path, 1e-3, 0.02); }),
            "poses.txt: no pose within 1 ms of frame 0 (time stamp 100.050000 s), nor two within 0.02 s around it");

  Trajectory log = t;
  log.has_timestamps = false;
  const auto in_order = PosesForFrames(log, {7.0, 8.0, 9.0}, "t.log");
  ASSERT_EQ(in_order.size(), 3u);
  EXPECT_TRUE(in_order[2].isApprox(t.world_from_camera[2]));
  EXPECT_EQ(testing::InputErrorMessage([&] {
              PosesForFrames(log, {7.0, 8.0}, "t.log");
            }),
            "t.log: 3 poses for 2 frames (a file without time stamps needs one pose per frame, in order)");
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
  WriteFileAtomic(path, "dataset tum\nintrinsics_matrix 0 0 320 0 500 240 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadConf(path); }),
            path.string() + ":2: focal length must be positive (fx=0, fy=500)");
}

}  // namespace
}  // namespace f2c
