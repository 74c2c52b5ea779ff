// Every reader on the real folders of ../shared/data (skipped when absent). Expected counts
// and intrinsics are those the data's README documents.

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "f2c/io/image.h"
#include "f2c/io/sequence.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

fs::path Data(const std::string& name) { return fs::path(F2C_SHARED_DATA_DIR) / name; }

#define SKIP_IF_ABSENT(name) \
  if (!fs::exists(Data(name))) GTEST_SKIP() << Data(name) << " absent: ../shared/data is not here"

// Median valid depth of a frame, metres.
double MedianDepth(const RgbdSequence& seq, const RgbdFrame& frame) {
  const cv::Mat d = LoadDepthMeters(seq, frame);
  std::vector<float> v;
  for (int y = 0; y < d.rows; y += 4) {
    for (int x = 0; x < d.cols; x += 4) {
      if (d.at<float>(y, x) > 0) v.push_back(d.at<float>(y, x));
    }
  }
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

TEST(RealData, TumFr1Xyz) {
  SKIP_IF_ABSENT("tum_fr1_xyz_15hz");
  IoOptions io;
  io.intrinsics = "tum-fr1";
  const RgbdSequence seq = ReadSequence(Data("tum_fr1_xyz_15hz"), io);
  EXPECT_EQ(seq.layout, DatasetLayout::kTum);
  EXPECT_EQ(seq.frames.size(), 396u);
  EXPECT_DOUBLE_EQ(seq.intrinsics->fx, 517.3);
  ASSERT_TRUE(seq.ground_truth.has_value());
  EXPECT_GT(seq.ground_truth->size(), 2500u);  // 100 Hz motion capture over ~27 s
  const double z = MedianDepth(seq, seq.frames[0]);
  EXPECT_GT(z, 0.5);  // a desk scene seen from about a metre or two
  EXPECT_LT(z, 3.0);
}

TEST(RealData, TumFr1Desk9) {
  SKIP_IF_ABSENT("tum_fr1_desk_9");
  const RgbdSequence seq = ReadSequence(Data("tum_fr1_desk_9"));
  EXPECT_EQ(seq.frames.size(), 9u);
  EXPECT_FALSE(seq.intrinsics.has_value());
  EXPECT_TRUE(seq.ground_truth.has_value());
  for (const RgbdFrame& f : seq.frames) {
    // Association within 0.02 s: colour and depth stamps come from the file names.
    EXPECT_LT(std::abs(std::stod(f.depth_path.stem().string()) - f.timestamp), 0.02);
  }
}

TEST(RealData, SevenScenesRedkitchen) {
  SKIP_IF_ABSENT("7scenes_redkitchen_15hz");
  const RgbdSequence seq = ReadSequence(Data("7scenes_redkitchen_15hz"));
  EXPECT_EQ(seq.layout, DatasetLayout::kSevenScenes);
  EXPECT_EQ(seq.frames.size(), 500u);
  EXPECT_DOUBLE_EQ(seq.intrinsics->fx, 585.0);
  EXPECT_DOUBLE_EQ(seq.intrinsics->cx, 320.0);
  ASSERT_TRUE(seq.ground_truth.has_value());
  EXPECT_EQ(seq.ground_truth->size(), 500u);
  EXPECT_NEAR(seq.frames[1].timestamp, 2 / 30.0, 1e-12);  // frame-000002
  const double z = MedianDepth(seq, seq.frames[0]);
  EXPECT_GT(z, 0.5);
  EXPECT_LT(z, 4.0);
}

TEST(RealData, Sun3dStudyroomIn3dMatchLayout) {
  SKIP_IF_ABSENT("sun3d_mit76_studyroom_5");
  const RgbdSequence seq = ReadSequence(Data("sun3d_mit76_studyroom_5"));
  EXPECT_EQ(seq.layout, DatasetLayout::kSevenScenes);  // frames under seq-01/
  EXPECT_EQ(seq.frames.size(), 5u);
  EXPECT_NEAR(seq.intrinsics->fx, 570.342205, 1e-6);
  ASSERT_TRUE(seq.ground_truth.has_value());
  EXPECT_EQ(seq.ground_truth->size(), 5u);
  EXPECT_NEAR(seq.ground_truth->world_from_camera[0].translation().x(), 1.973046, 1e-6);
  const double z = MedianDepth(seq, seq.frames[0]);
  EXPECT_GT(z, 0.5);
  EXPECT_LT(z, 5.0);
}

TEST(RealData, Open3dTestData) {
  SKIP_IF_ABSENT("open3d_testdata_rgbd");
  const RgbdSequence seq = ReadSequence(Data("open3d_testdata_rgbd"));
  EXPECT_EQ(seq.layout, DatasetLayout::kRedwood);
  EXPECT_EQ(seq.frames.size(), 5u);
  EXPECT_DOUBLE_EQ(seq.intrinsics->cx, 319.5);  // the README's 525 525 319.5 239.5
  ASSERT_TRUE(seq.ground_truth.has_value());
  ASSERT_EQ(seq.ground_truth->size(), 5u);
  EXPECT_NEAR(seq.ground_truth->world_from_camera[1].translation().y(), 0.5963093994288613, 1e-12);
  const double z = MedianDepth(seq, seq.frames[0]);
  EXPECT_GT(z, 0.5);
  EXPECT_LT(z, 5.0);
}

// The same scene point in SUN3D's own bit-rotated encoding and as plain millimetres: the
// other_formats/SUN_depth.png frame must decode to plausible indoor depths only with the
// rotation.
TEST(RealData, Sun3dBitRotatedDepthDecodes) {
  SKIP_IF_ABSENT("open3d_testdata_rgbd");
  const fs::path path = Data("open3d_testdata_rgbd") / "other_formats" / "SUN_depth.png";
  RgbdSequence seq;
  seq.depth_encoding = DepthEncoding::kSun3dBitRotated;
  RgbdFrame frame;
  frame.depth_path = path;
  const double rotated = MedianDepth(seq, frame);
  EXPECT_GT(rotated, 0.5);
  EXPECT_LT(rotated, 5.0);
  seq.depth_encoding = DepthEncoding::kPlain;
  EXPECT_GT(MedianDepth(seq, frame), 5.0);  // undecoded values are 8x too large
}

}  // namespace
}  // namespace f2c
