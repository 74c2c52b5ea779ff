// ROS 1 bags through the command line: bags written by Debian's python3-rosbag (an
// implementation of the format independent of ours, tests/tools/write_rosbag.py) from a
// simulated TUM folder give the folder's trajectory; damaged bags give one line each.

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/io/trajectory.h"
#include "f2c/testing/ros2_writer.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"
#include "tests/cli_helpers.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;
using namespace cli_test;

constexpr const char* kIntrinsics = "525,525,319.5,239.5";

// Writes `folder` as a bag; false where python3-rosbag is missing (the test then skips).
bool WriteBag(const fs::path& folder, const fs::path& bag, const std::string& options) {
  // Debian's interpreter, which has python3-rosbag, before any other on the PATH (pyenv's).
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  const std::string command = fmt::format("{} {}/tests/tools/write_rosbag.py {} {} --intrinsics {} {} 2>&1", python,
                                          F2C_SOURCE_DIR, folder.string(), bag.string(), kIntrinsics, options);
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  while (pipe != nullptr && fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  const int status = pipe == nullptr ? -1 : pclose(pipe);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 77) return false;
  EXPECT_EQ(status, 0) << output;
  return true;
}

// T0 of the input (the odometry is where colour and depth meet; the refinement adds nothing
// to the comparison), as trajectory.txt's text.
std::string T0(const std::string& input, const std::string& extra, const fs::path& out) {
  const Result r = RunCli("register " + input + " -q --no-report --stop-after odometry -o " + out.string() + extra);
  EXPECT_EQ(r.code, 0) << r.output;
  return ReadFileToString(out / "trajectory.txt");
}

// 32FC1 depth as ROS's compressedDepth (a 16-bit PNG of inverse depth q = A / z + B, with A
// and B in its header) reads back to the folder's depth within its quantisation (z^2 / A, plus
// our 0.2 mm unit), with the folder's invalid pixels; a header of another format is refused.
TEST(CliRosbag, CompressedDepthOf32FC1ReadsToItsQuantisation) {
  const fs::path folder = SyntheticTum("cli_bag_cdepth_folder", 3);
  const fs::path dir = testing::FreshTempDir("cli_bag_cdepth");
  const fs::path bag = dir / "c.bag";
  if (!WriteBag(folder, bag, "--compressed-depth")) GTEST_SKIP() << "python3-rosbag absent";
  IoOptions io;
  io.intrinsics = kIntrinsics;
  const RgbdSequence from_folder = ReadSequence(folder, io), from_bag = ReadSequence(bag);
  ASSERT_EQ(from_bag.frames.size(), from_folder.frames.size());
  const double quant_a = 100.0 * 101.0;  // the transport's default (depth_quantization 100)
  for (size_t k = 0; k < from_bag.frames.size(); ++k) {
    const cv::Mat a = LoadDepthMeters(from_folder, from_folder.frames[k]);
    const cv::Mat b = LoadDepthMeters(from_bag, from_bag.frames[k]);
    ASSERT_EQ(a.size(), b.size());
    int valid = 0, off = 0;
    for (int y = 0; y < a.rows; ++y) {
      for (int x = 0; x < a.cols; ++x) {
        const float za = a.at<float>(y, x), zb = b.at<float>(y, x);
        ASSERT_EQ(za > 0, zb > 0) << k << " " << x << "," << y;
        if (za <= 0) continue;
        ++valid;
        off += std::abs(za - zb) > za * za / quant_a + 2e-4 + 1e-6;
      }
    }
    EXPECT_GT(valid, 100000) << k;
    EXPECT_EQ(off, 0) << k;
  }
  const Result info = RunCli("info " + bag.string());
  EXPECT_NE(info.output.find("stream       depth: /camera/depth/image/compressedDepth (32FC1; compressedDepth, 3 "
                             "images)"),
            std::string::npos)
      << info.output;
  ASSERT_TRUE(WriteBag(folder, dir / "format1.bag", "--compressed-depth 1"));
  const Result bad = RunCli("info " + (dir / "format1.bag").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_EQ(bad.output,
            fmt::format("error: {} (/camera/depth/image/compressedDepth at {:.6f} s): compressedDepth 32FC1 "
                        "header: format 1, quantisation 10100 and -1009 (expected format 0, inverse depth, "
                        "and finite constants)\n",
                        (dir / "format1.bag").string(), from_bag.frames[0].timestamp));
}

TEST(CliRosbag, ATumLayoutBagGivesItsFoldersTrajectoryWhateverItsCompression) {
  const fs::path folder = SyntheticTum("cli_bag_folder", 5);
  const fs::path dir = testing::FreshTempDir("cli_bag");
  if (!WriteBag(folder, dir / "none.bag", "")) GTEST_SKIP() << "python3-rosbag absent (scripts/setup.sh installs it)";
  const std::string from_folder = T0(folder.string(), std::string(" --intrinsics ") + kIntrinsics, dir / "folder");
  ASSERT_FALSE(from_folder.empty());
  for (const char* compression : {"none", "bz2", "lz4"}) {
    const fs::path bag = dir / (std::string(compression) + ".bag");
    if (!fs::exists(bag)) {
      ASSERT_TRUE(WriteBag(folder, bag, std::string("--compression ") + compression));
    }
    // Identical frames (32FC1 depth read back to the PNGs' values, the same stamps and
    // pairing): the same poses to the last digit.
    EXPECT_EQ(T0(bag.string(), "", dir / (std::string("out_") + compression)), from_folder) << compression;
  }
  const Result info = RunCli("info " + (dir / "lz4.bag").string());
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("layout       rosbag"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("stream       depth: /camera/depth/image (32FC1, 5 images)"), std::string::npos)
      << info.output;
  EXPECT_NE(info.output.find("stream       colour: /camera/rgb/image_color (rgb8, 5 images)"), std::string::npos)
      << info.output;
  EXPECT_NE(info.output.find("intrinsics   fx 525.000 fy 525.000 cx 319.500 cy 239.500 (" + (dir / "lz4.bag").string() +
                             " (/camera/depth/camera_info))"),
            std::string::npos)
      << info.output;
  // --first/--last/--every select from the bag's frames as from a folder's.
  auto stamps = [&](const std::string& input) {
    const Result r =
        RunCli("info --json --first 1 --last 4 --every 2 --intrinsics " + std::string(kIntrinsics) + " " + input);
    EXPECT_EQ(r.code, 0) << r.output;
    std::vector<double> out;
    const nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
    for (const nlohmann::json& f : j["frames"]) {
      out.push_back(f["timestamp"].get<double>());
    }
    EXPECT_EQ(out.size(), 2u) << r.output;
    return out;
  };
  EXPECT_EQ(stamps((dir / "none.bag").string()), stamps(folder.string()));
}

// Real frames (TUM fr1/desk, 9 frames; colour stored as JPEG) with the colour as
// CompressedImage messages holding the folder's own JPEG files: the folder's poses exactly.
TEST(CliRosbag, ARealTumSequenceAndItsBagGiveTheSamePoses) {
  const fs::path folder = Data("tum_fr1_desk_9");
  if (!fs::exists(folder)) GTEST_SKIP() << "../shared/data absent";
  const fs::path dir = testing::FreshTempDir("cli_bag_real");
  if (!WriteBag(folder, dir / "desk.bag", "--compression lz4 --compressed-color")) {
    GTEST_SKIP() << "python3-rosbag absent (scripts/setup.sh installs it)";
  }
  EXPECT_EQ(T0((dir / "desk.bag").string(), " --intrinsics tum-fr1", dir / "bag"),
            T0(folder.string(), " --intrinsics tum-fr1", dir / "folder"));
}

TEST(CliRosbag, ARealSenseRecordingIsFoundByItsTopics) {
  const fs::path folder = SyntheticTum("cli_bag_rs_folder", 5);
  const fs::path dir = testing::FreshTempDir("cli_bag_rs");
  if (!WriteBag(folder, dir / "rs.bag", "--layout realsense --compression lz4 --color-encoding bgr8")) {
    GTEST_SKIP() << "python3-rosbag absent (scripts/setup.sh installs it)";
  }
  const Result info = RunCli("info " + (dir / "rs.bag").string());
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("stream       depth: /device_0/sensor_0/Depth_0/image/data (mono16, 5 images)"),
            std::string::npos)
      << info.output;
  // The Depth Units option (float32 1/5000 m).
  EXPECT_NE(info.output.find("0.0002 m per unit"), std::string::npos) << info.output;
  // The colour stream another camera: its camera info, and its place from the streams' tf/0
  // (each stream's pose in the reference stream's frame; the depth stream is the reference).
  ASSERT_TRUE(WriteBag(folder, dir / "two_cameras.bag", "--layout realsense --color-camera 600,605,330,250,0.025,0,0"));
  const Result two = RunCli("info --json " + (dir / "two_cameras.bag").string());
  ASSERT_EQ(two.code, 0) << two.output;
  const nlohmann::json color = nlohmann::json::parse(two.output)["color_camera"];
  EXPECT_EQ(color["fx"].get<double>(), 600);
  EXPECT_EQ(color["cy"].get<double>(), 250);
  const std::vector<double> color_from_depth = color["color_from_depth"].get<std::vector<double>>();
  EXPECT_NEAR(color_from_depth[3], -0.025, 1e-12);  // row-major: the depth camera 25 mm to the colour's left
  EXPECT_NEAR(color_from_depth[0], 1, 1e-12);
  // Another bag's colour camera, placed by /tf_static (both cameras' frames under camera_link).
  ASSERT_TRUE(WriteBag(folder, dir / "tf_static.bag", "--color-camera 600,605,330,250,0.025,0,0"));
  const Result tf = RunCli("info --json " + (dir / "tf_static.bag").string());
  ASSERT_EQ(tf.code, 0) << tf.output;
  const std::vector<double> tf_color_from_depth =
      nlohmann::json::parse(tf.output.substr(tf.output.find('{')))["color_camera"]["color_from_depth"]
          .get<std::vector<double>>();
  EXPECT_NEAR(tf_color_from_depth[3], -0.025, 1e-12);
  EXPECT_EQ(tf.output.find("warning"), std::string::npos) << tf.output;
  // Depth in 1/5000 m as the folder's, with float32's rounding of the unit: the folder's
  // poses within a tenth of a millimetre.
  T0(folder.string(), std::string(" --intrinsics ") + kIntrinsics, dir / "folder");
  T0((dir / "rs.bag").string(), "", dir / "bag");
  const Trajectory from_folder = ReadTumTrajectory(dir / "folder" / "trajectory.txt");
  const Trajectory from_bag = ReadTumTrajectory(dir / "bag" / "trajectory.txt");
  ASSERT_EQ(from_bag.size(), from_folder.size());
  for (size_t i = 0; i < from_bag.size(); ++i) {
    EXPECT_EQ(from_bag.timestamps[i], from_folder.timestamps[i]);
    EXPECT_LT((from_bag.world_from_camera[i].translation() - from_folder.world_from_camera[i].translation()).norm(),
              1e-4);
  }
}

// Every damaged or unreadable bag: exit 1, one line naming the bag and what is wrong, and no
// output written.
TEST(CliRosbag, DamagedBagsAreOneLineErrors) {
  const fs::path folder = SyntheticTum("cli_bag_bad_folder", 3);
  const fs::path dir = testing::FreshTempDir("cli_bag_bad");
  if (!WriteBag(folder, dir / "good.bag", "--compression lz4")) {
    GTEST_SKIP() << "python3-rosbag absent (scripts/setup.sh installs it)";
  }
  ASSERT_TRUE(WriteBag(folder, dir / "bayer.bag", "--color-encoding bayer_rggb8"));
  ASSERT_TRUE(WriteBag(folder, dir / "no_info.bag", "--no-camera-info"));
  ASSERT_TRUE(WriteBag(folder, dir / "two.bag", "--extra-color-topic /camera2/image"));
  const std::string good = ReadFileToString(dir / "good.bag");
  WriteFileAtomic(dir / "cut.bag", good.substr(0, good.size() / 2));
  std::string zst = good;
  for (size_t at = zst.find("compression=lz4"); at != std::string::npos; at = zst.find("compression=lz4", at)) {
    zst.replace(at, 15, "compression=zst");
  }
  WriteFileAtomic(dir / "zst.bag", zst);
  std::string old = good;
  old.replace(0, 13, "#ROSBAG V1.2\n");
  WriteFileAtomic(dir / "old.bag", old);
  auto error = [&](const std::string& input, const std::string& extra = "") {
    const fs::path out = dir / "out";
    const Result r = RunCli("register " + (dir / input).string() + " -q -o " + out.string() + extra);
    EXPECT_EQ(r.code, 1) << r.output;
    EXPECT_FALSE(fs::exists(out / "trajectory.txt"));
    return r.output;
  };
  const std::string bag = (dir / "good.bag").string();
  EXPECT_NE(error("cut.bag").find(fmt::format("lies past its end ({} bytes): the bag is cut short", good.size() / 2)),
            std::string::npos);
  EXPECT_NE(error("zst.bag").find("is compressed as 'zst', which fine2coarse does not read (none, bz2, lz4)"),
            std::string::npos);
  EXPECT_EQ(error("old.bag"), "error: " + (dir / "old.bag").string() +
                                  ": ROS bag format 1.2 (fine2coarse reads 2.0; `rosbag fix` converts older bags)\n");
  EXPECT_EQ(error("good.bag", " --depth-topic /nope"),
            "error: " + bag +
                ": --depth-topic: no topic '/nope' in the bag (its sensor_msgs/Image, sensor_msgs/CompressedImage "
                "topics: /camera/depth/image, /camera/rgb/image_color)\n");
  EXPECT_EQ(error("good.bag", " --color-topic /camera/rgb/camera_info"),
            "error: " + bag +
                ": --color-topic: topic '/camera/rgb/camera_info' holds sensor_msgs/CameraInfo, not sensor_msgs/Image, "
                "sensor_msgs/CompressedImage\n");
  EXPECT_EQ(error("bayer.bag"), "error: " + (dir / "bayer.bag").string() +
                                    " (/camera/rgb/image_color at 1000.000000 s): image encoding 'bayer_rggb8', which "
                                    "fine2coarse does not read (depth: 16UC1, mono16, 32FC1; colour: rgb8, bgr8, "
                                    "rgba8, bgra8, mono8, yuv422, yuv422_yuy2)\n");
  EXPECT_EQ(error("no_info.bag"), "error: " + (dir / "no_info.bag").string() +
                                      ": no camera info for /camera/depth/image (its CameraInfo topics: none): pass "
                                      "--intrinsics or --camera-info-topic\n");
  EXPECT_EQ(error("two.bag"), "error: " + (dir / "two.bag").string() +
                                  ": 2 colour image topics (/camera/rgb/image_color, /camera2/image): choose one with "
                                  "--color-topic\n");
  EXPECT_EQ(RunCli("info " + (dir / "two.bag").string() + " --color-topic /camera2/image").code, 0);
  // With --intrinsics the same bag reads.
  const Result r = RunCli("info " + (dir / "no_info.bag").string() + " --intrinsics " + kIntrinsics);
  EXPECT_EQ(r.code, 0) << r.output;
}

// ROS 2 bags, SQLite and MCAP (chunks uncompressed, zstd, lz4), written from the formats'
// specifications (testing/ros2_writer): the folder's poses to the last digit, as a bag folder
// (metadata.yaml) or as the storage file alone.
TEST(CliRosbag, Ros2BagsGiveTheirFoldersTrajectory) {
  const fs::path folder = SyntheticTum("cli_bag2_folder", 4);
  const fs::path dir = testing::FreshTempDir("cli_bag2");
  const std::string from_folder = T0(folder.string(), std::string(" --intrinsics ") + kIntrinsics, dir / "folder");
  ASSERT_FALSE(from_folder.empty());
  testing::Ros2BagOptions o;
  o.intrinsics = testing::TestIntrinsics();
  for (const auto& [storage, compression] :
       std::vector<std::pair<std::string, std::string>>{{"db3", ""}, {"mcap", ""}, {"mcap", "zstd"}, {"mcap", "lz4"}}) {
    o.storage = storage;
    o.compression = compression;
    const fs::path bag = dir / (storage + compression);
    const fs::path file = testing::WriteRos2Bag(folder, bag, o);
    EXPECT_EQ(T0(bag.string(), "", dir / ("out_" + storage + compression)), from_folder) << storage << compression;
    if (compression == "zstd") {  // the .mcap file alone reads as its folder
      auto frames = [&](const fs::path& input) {
        const Result r = RunCli("info --json " + input.string());
        return nlohmann::json::parse(r.output.substr(r.output.find('{')))["frames"];
      };
      EXPECT_EQ(frames(file), frames(bag));
    }
  }
  const Result info = RunCli("info " + (dir / "mcapzstd").string());
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("stream       format: ROS 2 bag (MCAP, CDR)"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("stream       depth: /camera/depth/image_rect_raw (32FC1, 4 images)"), std::string::npos)
      << info.output;
  const Result db3 = RunCli("info " + (dir / "db3").string());
  EXPECT_NE(db3.output.find("stream       format: ROS 2 bag (SQLite .db3, CDR)"), std::string::npos) << db3.output;

  // The colour camera placed by /tf_static (CDR tf2_msgs/msg/TFMessage).
  o.storage = "db3";
  o.color_intrinsics = CameraIntrinsics{600, 605, 330, 250, 640, 480};
  o.color_in_depth = Eigen::Vector3d(0.025, 0, 0);
  testing::WriteRos2Bag(folder, dir / "tf_static", o);
  const Result tf = RunCli("info --json " + (dir / "tf_static").string());
  ASSERT_EQ(tf.code, 0) << tf.output;
  const nlohmann::json tf_json = nlohmann::json::parse(tf.output.substr(tf.output.find('{')));
  EXPECT_EQ(tf_json["color_camera"]["fx"].get<double>(), 600);
  EXPECT_NEAR(tf_json["color_camera"]["color_from_depth"][3].get<double>(), -0.025, 1e-12);

  // Damaged: cut short, an unknown compression, a database that is not a bag.
  const std::string mcap = ReadFileToString(dir / "mcapzstd" / "scan.mcap");
  WriteFileAtomic(dir / "cut.mcap", mcap.substr(0, mcap.size() - 100));
  std::string brotli = mcap;
  for (size_t at = brotli.find("zstd"); at != std::string::npos; at = brotli.find("zstd", at)) {
    brotli.replace(at, 4, "brot");
  }
  WriteFileAtomic(dir / "brotli.mcap", brotli);
  auto error = [&](const fs::path& input) {
    const Result r = RunCli("register " + input.string() + " -q -o " + (dir / "bad").string());
    EXPECT_EQ(r.code, 1) << r.output;
    return r.output;
  };
  EXPECT_EQ(error(dir / "cut.mcap"),
            "error: " + (dir / "cut.mcap").string() + ": MCAP cut short (no footer and closing magic at its end)\n");
  EXPECT_NE(
      error(dir / "brotli.mcap").find("is compressed as 'brot', which fine2coarse does not read (none, zstd, lz4)"),
      std::string::npos);
  WriteFileAtomic(dir / "empty.db3", std::string("SQLite format 3\0", 16) + std::string(84, '\0'));
  EXPECT_EQ(error(dir / "empty.db3"),
            "error: " + (dir / "empty.db3").string() + ": not a ROS 2 bag database (file is not a database)\n");
  EXPECT_FALSE(fs::exists(dir / "bad" / "trajectory.txt"));
}

}  // namespace
}  // namespace f2c
