#include "f2c/io/sequence.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <functional>
#include <opencv2/imgcodecs.hpp>

#include "f2c/io/image.h"
#include "f2c/testing/log_capture.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/text.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;
using Poses = std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>;

Poses Line(int n) {
  Poses poses;
  for (int i = 0; i < n; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.translation() = Eigen::Vector3d(0.02 * i, 0, -0.5);
    poses.push_back(pose);
  }
  return poses;
}

fs::path TumFolder(const std::string& name, int n) {
  const fs::path dir = testing::FreshTempDir(name);
  testing::WriteTumSequence(dir, testing::SyntheticScene(), testing::TestIntrinsics(), Line(n));
  return dir;
}

TEST(DetectLayout, MissingEmptyAndUnknown) {
  const fs::path root = testing::FreshTempDir("layout");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(root / "absent"); }),
            (root / "absent").string() + ": no such file or folder");
  fs::create_directories(root / "empty");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(root / "empty"); }),
            (root / "empty").string() + ": folder is empty");
  fs::create_directories(root / "other");
  WriteFileAtomic(root / "other" / "notes.txt", "hello");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(root / "other"); }),
            (root / "other").string() +
                ": unknown dataset layout (expected TUM rgb.txt + depth.txt, 7-Scenes/3DMatch "
                "frame-*.depth.png, SUN3D image/ + depth/ + intrinsics.txt, Redwood color/ + depth/, "
                "one .conf file, or a ROS 2 bag's metadata.yaml)");
}

TEST(ReadTum, AssociatesAndReadsGroundTruth) {
  const fs::path dir = TumFolder("tum_ok", 5);
  const RgbdSequence seq = ReadSequence(dir);
  EXPECT_EQ(seq.layout, DatasetLayout::kTum);
  ASSERT_EQ(seq.frames.size(), 5u);
  // The depth image's stamp (the folder's depth lies 1 ms after its colour), and the colour's
  // offset from it.
  EXPECT_NEAR(seq.frames[2].timestamp, 1000.0 + 2 / 30.0 + 0.001, 1e-6);
  EXPECT_NEAR(seq.frames[2].color_time, -0.001, 1e-6);
  IoOptions by_color;
  by_color.stamp = FrameStamp::kColor;
  const RgbdSequence colour_stamped = ReadSequence(dir, by_color);
  EXPECT_NEAR(colour_stamped.frames[2].timestamp, 1000.0 + 2 / 30.0, 1e-6);
  EXPECT_NEAR(colour_stamped.frames[2].color_time, 0.0, 1e-9);
  EXPECT_FALSE(seq.intrinsics.has_value());
  EXPECT_DOUBLE_EQ(seq.depth_scale, 1.0 / 5000.0);
  ASSERT_TRUE(seq.ground_truth.has_value());
  EXPECT_EQ(seq.ground_truth->size(), 5u);
  // Depth decodes to the rendered metres (quantised to 1/5000 m).
  const cv::Mat depth = LoadDepthMeters(seq, seq.frames[0]);
  const cv::Mat truth = testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), Line(1)[0]).depth;
  EXPECT_NEAR(depth.at<float>(240, 320), truth.at<float>(240, 320), 1.0 / 5000.0);
}

TEST(ReadTum, FrameSelection) {
  const fs::path dir = TumFolder("tum_select", 6);
  IoOptions io;
  io.first = 1;
  io.every = 2;
  const RgbdSequence seq = ReadSequence(dir, io);
  ASSERT_EQ(seq.frames.size(), 3u);  // frames 1, 3, 5
  EXPECT_NEAR(seq.frames[1].timestamp, 1000.0 + 3 / 30.0 + 0.001, 1e-6);
  io.first = 10;
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir, io); }),
            dir.string() + ": frame selection --first 10 --last -1 leaves no frame (the sequence has 6)");
}

TEST(ReadTum, NoDepthWithinTheAssociationWindow) {
  const fs::path dir = TumFolder("tum_far", 2);
  WriteFileAtomic(dir / "depth.txt", "5000.0 depth/x.png\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            (dir / "depth.txt").string() + ": no depth image within 0.02 s of a colour image in rgb.txt");
}

TEST(ReadTum, MalformedRgbTxt) {
  const fs::path dir = TumFolder("tum_bad_list", 2);
  WriteFileAtomic(dir / "rgb.txt", "# color\n1000.0 rgb/a.png\n1000.1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            (dir / "rgb.txt").string() + ":3: expected 'timestamp filename'");
}

// Lists out of time order are read in time order (one warning each; our own evaluate and
// fuse refuse a trajectory that is not); a time stamp listed twice is an error; colour
// images without depth are counted in one warning.
TEST(ReadTum, ListsInTimeOrderTimeStampsOnceAndDroppedImagesCounted) {
  const fs::path dir = TumFolder("tum_order", 4);
  const RgbdSequence in_order = ReadSequence(dir);
  auto lines = [&](const std::string& list) {
    std::vector<std::string> out;
    for (const TextLine& line : ReadDataLines(dir / list)) out.push_back(line.text);
    return out;
  };
  const std::vector<std::string> rgb = lines("rgb.txt"), depth = lines("depth.txt");
  ASSERT_EQ(rgb.size(), 4u);
  WriteFileAtomic(dir / "rgb.txt", rgb[2] + "\n" + rgb[0] + "\n" + rgb[3] + "\n" + rgb[1] + "\n");
  {
    testing::LogCapture log;
    const RgbdSequence sorted = ReadSequence(dir);
    ASSERT_EQ(sorted.frames.size(), 4u);
    for (size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(sorted.frames[k].timestamp, in_order.frames[k].timestamp);
      EXPECT_EQ(sorted.frames[k].color_path, in_order.frames[k].color_path);
      EXPECT_EQ(sorted.frames[k].depth_path, in_order.frames[k].depth_path);
    }
    EXPECT_EQ(log.Lines(), std::vector<std::string>{(dir / "rgb.txt").string() +
                                                    ": images listed out of time order; read in time order"});
  }
  WriteFileAtomic(dir / "rgb.txt", rgb[0] + "\n" + rgb[1] + "\n" + rgb[1] + "\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            (dir / "rgb.txt").string() + fmt::format(":3: time stamp {:.6f} listed again (line 2)",
                                                     in_order.frames[1].timestamp + in_order.frames[1].color_time));
  WriteFileAtomic(dir / "rgb.txt", rgb[0] + "\n" + rgb[1] + "\n" + rgb[2] + "\n" + rgb[3] + "\n");
  WriteFileAtomic(dir / "depth.txt", depth[0] + "\n" + depth[3] + "\n");
  testing::LogCapture log;
  EXPECT_EQ(ReadSequence(dir).frames.size(), 2u);
  EXPECT_EQ(log.Lines(), std::vector<std::string>{(dir / "rgb.txt").string() +
                                                  ": 2 of 4 colour images have no depth image within 0.02 s "
                                                  "(depth.txt): left out"});
}

TEST(ReadTum, MissingFrameImage) {
  const fs::path dir = TumFolder("tum_missing", 3);
  const RgbdSequence seq = ReadSequence(dir);
  fs::remove(seq.frames[1].color_path);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            seq.frames[1].color_path.string() + ": missing frame image (listed in the dataset)");
}

TEST(ReadTum, IntrinsicsOption) {
  const fs::path dir = TumFolder("tum_k", 2);
  IoOptions io;
  io.intrinsics = "tum-fr2";
  EXPECT_DOUBLE_EQ(ReadSequence(dir, io).intrinsics->fx, 520.9);
  io.intrinsics = "525,0,320,240";
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir, io); }),
            "--intrinsics: focal length must be positive (fx=525, fy=0)");
}

// A 7-Scenes folder: frame-XXXXXX.{color.png,depth.png,pose.txt} + camera-intrinsics.txt.
fs::path SevenScenesFolder(const std::string& name, int n) {
  const fs::path dir = testing::FreshTempDir(name);
  const auto poses = Line(n);
  for (int i = 0; i < n; ++i) {
    const auto frame = testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), poses[i]);
    cv::Mat mm;
    frame.depth.convertTo(mm, CV_16U, 1000.0);
    const std::string stem = fmt::format("frame-{:06d}", 2 * i);
    cv::imwrite((dir / (stem + ".color.png")).string(), frame.color);
    cv::imwrite((dir / (stem + ".depth.png")).string(), mm);
    const Eigen::Matrix4d m = poses[i].matrix();
    WriteFileAtomic(dir / (stem + ".pose.txt"),
                    fmt::format("1 0 0 {}\n0 1 0 {}\n0 0 1 {}\n0 0 0 1\n", m(0, 3), m(1, 3), m(2, 3)));
  }
  WriteFileAtomic(dir / "camera-intrinsics.txt", "525 0 319.5\n0 525 239.5\n0 0 1\n");
  return dir;
}

TEST(ReadSevenScenes, FramesPosesIntrinsics) {
  const fs::path dir = SevenScenesFolder("7s_ok", 3);
  const RgbdSequence seq = ReadSequence(dir);
  EXPECT_EQ(seq.layout, DatasetLayout::kSevenScenes);
  ASSERT_EQ(seq.frames.size(), 3u);
  EXPECT_NEAR(seq.frames[2].timestamp, 4 / 30.0, 1e-12);  // frame-000004
  EXPECT_DOUBLE_EQ(seq.intrinsics->cx, 319.5);
  ASSERT_EQ(seq.ground_truth->size(), 3u);
  EXPECT_NEAR(seq.ground_truth->world_from_camera[2].translation().x(), 0.04, 1e-12);
}

// A 3x3 matrix file carries no image size: it comes from the first depth image, so a
// camera of another resolution (a RealSense at 848x480, say) reads, and every frame must
// then match it.
TEST(ReadSevenScenes, IntrinsicsTakeTheImageSize) {
  const fs::path dir = testing::FreshTempDir("seven_scenes_848");
  const CameraIntrinsics k{420.0, 420.0, 700.0, 240.0, 848, 480};  // cx beyond 640
  Rigid3d pose = Rigid3d::Identity();
  pose.translation() = Eigen::Vector3d(0, 0, -0.5);
  for (int i = 0; i < 2; ++i) {
    const auto frame = testing::Render(testing::SyntheticScene(), k, pose);
    cv::Mat mm;
    frame.depth.convertTo(mm, CV_16U, 1000.0);
    cv::imwrite((dir / fmt::format("frame-{:06d}.color.png", i)).string(), frame.color);
    cv::imwrite((dir / fmt::format("frame-{:06d}.depth.png", i)).string(), i == 0 ? mm : mm(cv::Rect(0, 0, 640, 480)));
  }
  WriteFileAtomic(dir / "camera-intrinsics.txt", "420 0 700\n0 420 240\n0 0 1\n");
  const RgbdSequence seq = ReadSequence(dir);
  EXPECT_EQ(seq.intrinsics->width, 848);
  EXPECT_EQ(seq.intrinsics->height, 480);
  EXPECT_EQ(LoadDepthMeters(seq, seq.frames[0]).cols, 848);
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(seq, seq.frames[1]); }),
            seq.frames[1].depth_path.string() + ": depth image is 640x480 but the intrinsics (" +
                (dir / "camera-intrinsics.txt").string() + ") are for 848x480");
  // fx,fy,cx,cy on the command line, likewise; a principal point outside the image is an error.
  IoOptions io;
  io.intrinsics = "420,420,700,240";
  EXPECT_EQ(ReadSequence(dir, io).intrinsics->width, 848);
  io.intrinsics = "420,420,900,240";
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir, io); }),
            "--intrinsics 420,420,900,240: principal point (900, 240) lies outside the 848x480 image");
}

// 3DMatch-style seq-XX subfolders: all joined by default, one with --sequence, and a clear
// error naming the ones there for a wrong name.
TEST(ReadSevenScenes, SequenceSubfolders) {
  const fs::path dir = testing::FreshTempDir("seven_scenes_seqs");
  for (const char* seq : {"seq-01", "seq-02"}) {
    const fs::path sub = SevenScenesFolder(std::string("seven_scenes_seqs_") + seq, 2);
    fs::rename(sub, dir / seq);
  }
  fs::copy_file(dir / "seq-01" / "camera-intrinsics.txt", dir / "camera-intrinsics.txt");
  EXPECT_EQ(ReadSequence(dir).frames.size(), 4u);
  IoOptions io;
  io.sequence = "seq-02";
  const RgbdSequence two = ReadSequence(dir, io);
  ASSERT_EQ(two.frames.size(), 2u);
  EXPECT_EQ(two.frames[0].depth_path, dir / "seq-02" / "frame-000000.depth.png");
  EXPECT_EQ(two.ground_truth->size(), 2u);
  io.sequence = "seq-09";
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir, io); }),
            dir.string() + ": no sequence folder 'seq-09' (it has: seq-01, seq-02)");
}

TEST(ReadSevenScenes, NanAndNonRigidPoses) {
  const fs::path dir = SevenScenesFolder("7s_bad_pose", 2);
  WriteFileAtomic(dir / "frame-000002.pose.txt", "1 0 0 nan\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            (dir / "frame-000002.pose.txt").string() + ":1: 'nan' is not a finite number; expected a 4x4 pose matrix");
  WriteFileAtomic(dir / "frame-000002.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 3 0\n0 0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            (dir / "frame-000002.pose.txt").string() + ": pose is not rigid (max |R^T R - I| = 8, det R = 3)");
}

TEST(ReadSevenScenes, ZeroFocalLength) {
  const fs::path dir = SevenScenesFolder("7s_zero_f", 1);
  WriteFileAtomic(dir / "camera-intrinsics.txt", "0 0 320\n0 0 240\n0 0 1\n");
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            (dir / "camera-intrinsics.txt").string() + ": focal length must be positive (fx=0, fy=0)");
}

TEST(ReadSun3d, BitRotatedDepthTimestampsAndExtrinsics) {
  const fs::path dir = testing::FreshTempDir("sun3d");
  fs::create_directories(dir / "image");
  fs::create_directories(dir / "depth");
  fs::create_directories(dir / "extrinsics");
  WriteFileAtomic(dir / "intrinsics.txt", "570.3 0 320\n0 570.3 240\n0 0 1\n");
  std::string extrinsics;
  for (int i = 0; i < 2; ++i) {
    cv::Mat color(480, 640, CV_8UC3, cv::Scalar(10, 20, 30));
    cv::Mat depth(480, 640, CV_16U);
    const uint16_t mm = static_cast<uint16_t>(1500 + 100 * i);
    depth.setTo(static_cast<uint16_t>((mm << 3) | (mm >> 13)));  // SUN3D's rotated encoding
    // Colour at 33 ms steps; depth 5 ms later, so nearest-time pairing is checked.
    cv::imwrite((dir / "image" / fmt::format("{:07d}-{:012d}.jpg", i + 1, 33000 * i)).string(), color);
    cv::imwrite((dir / "depth" / fmt::format("{:07d}-{:012d}.png", i + 1, 33000 * i + 5000)).string(), depth);
    extrinsics += fmt::format("1 0 0 {}\n0 1 0 0\n0 0 1 0\n", 0.1 * i);
  }
  WriteFileAtomic(dir / "extrinsics" / "20140101000000.txt", extrinsics);
  const RgbdSequence seq = ReadSequence(dir);
  EXPECT_EQ(seq.layout, DatasetLayout::kSun3d);
  ASSERT_EQ(seq.frames.size(), 2u);
  EXPECT_NEAR(seq.frames[1].timestamp, 0.033, 1e-9);
  EXPECT_EQ(seq.frames[1].depth_path.filename().string(), "0000002-000000038000.png");
  EXPECT_FLOAT_EQ(LoadDepthMeters(seq, seq.frames[1]).at<float>(100, 100), 1.6f);
  ASSERT_TRUE(seq.ground_truth.has_value());
  EXPECT_NEAR(seq.ground_truth->world_from_camera[1].translation().x(), 0.1, 1e-12);
}

TEST(ReadRedwood, CountMismatchAndDefaultIntrinsics) {
  const fs::path dir = testing::FreshTempDir("redwood");
  fs::create_directories(dir / "color");
  fs::create_directories(dir / "depth");
  cv::Mat color(480, 640, CV_8UC3, cv::Scalar(0)), depth(480, 640, CV_16U, cv::Scalar(1000));
  for (int i = 0; i < 2; ++i) {
    cv::imwrite((dir / "color" / fmt::format("{:05d}.jpg", i)).string(), color);
    cv::imwrite((dir / "depth" / fmt::format("{:05d}.png", i)).string(), depth);
  }
  const RgbdSequence seq = ReadSequence(dir);
  EXPECT_EQ(seq.layout, DatasetLayout::kRedwood);
  EXPECT_DOUBLE_EQ(seq.intrinsics->fx, 525.0);
  EXPECT_FALSE(seq.ground_truth.has_value());
  cv::imwrite((dir / "depth" / "00002.png").string(), depth);
  EXPECT_EQ(testing::InputErrorMessage([&] { ReadSequence(dir); }),
            dir.string() + ": 2 colour images in color but 3 depth images in depth/");
}

TEST(ReadRedwood, Open3dIntrinsicsJsonIsChecked) {
  const fs::path dir = testing::FreshTempDir("redwood_json");
  fs::create_directories(dir / "color");
  fs::create_directories(dir / "depth");
  cv::Mat color(480, 640, CV_8UC3, cv::Scalar(0)), depth(480, 640, CV_16U, cv::Scalar(1000));
  cv::imwrite((dir / "color" / "00000.jpg").string(), color);
  cv::imwrite((dir / "depth" / "00000.png").string(), depth);
  const fs::path json = dir / "camera_intrinsic.json";
  WriteFileAtomic(json, R"({"width": 640, "height": 480, "intrinsic_matrix": [500, 0, 0, 0, 510, 0, 320, 240, 1]})");
  EXPECT_DOUBLE_EQ(ReadSequence(dir).intrinsics->fy, 510.0);
  auto message = [&](const std::string& text) {
    WriteFileAtomic(json, text);
    return testing::InputErrorMessage([&] { ReadSequence(dir); });
  };
  EXPECT_EQ(message(R"({"width": "wide", "intrinsic_matrix": [500, 0, 0, 0, 510, 0, 320, 240, 1]})"),
            json.string() + ": 'width' must be a whole number of pixels (1 to 100000)");
  EXPECT_EQ(message(R"({"intrinsic_matrix": [500, 0, 0]})"),
            json.string() + ": expected 'intrinsic_matrix' with 9 numbers (Open3D intrinsic JSON)");
  EXPECT_EQ(message("[1, 2]"), json.string() + ": expected 'intrinsic_matrix' with 9 numbers (Open3D intrinsic JSON)");
  EXPECT_EQ(message("{").rfind(json.string() + ": not valid JSON: ", 0), 0u);
}

}  // namespace
}  // namespace f2c
