// ScanNet .sens recordings, written byte by byte from the format's description
// (testing/sens_writer.h): frames, intrinsics, poses, depth, and colour from another camera
// resampled into the depth camera.

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "f2c/io/image.h"
#include "f2c/io/image_write.h"
#include "f2c/io/sequence.h"
#include "f2c/testing/sens_writer.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;
using PoseList = std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>;

PoseList Walk(int n) {
  PoseList poses;
  for (int i = 0; i < n; ++i) {
    Rigid3d pose = Rigid3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.03 * i, 0, -0.6);
    poses.push_back(pose);
  }
  return poses;
}

// A colour camera of its own: larger, other intrinsics, 2.5 cm beside the depth camera and
// turned 1 degree, as a RealSense's or a Kinect's two sensors are.
testing::SensOptions TwoCameras() {
  testing::SensOptions o;
  o.color = {600.0, 605.0, 405.0, 297.0, 800, 600};
  o.color_from_depth.linear() = Eigen::AngleAxisd(M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  o.color_from_depth.translation() = Eigen::Vector3d(-0.025, 0.002, 0.001);
  return o;
}

TEST(ReadSens, FramesIntrinsicsPosesAndDepth) {
  const fs::path path = testing::FreshTempDir("sens_read") / "scan.sens";
  const PoseList poses = Walk(3);
  testing::WriteSyntheticSens(path, testing::SyntheticScene(), poses, TwoCameras());
  const RgbdSequence seq = ReadSequence(path);
  EXPECT_EQ(seq.layout, DatasetLayout::kSens);
  ASSERT_EQ(seq.frames.size(), 3u);
  EXPECT_NEAR(seq.frames[2].timestamp, 1000.0 + 2 / 30.0, 1e-6);
  ASSERT_TRUE(seq.intrinsics);
  EXPECT_EQ(seq.intrinsics->width, 640);
  EXPECT_DOUBLE_EQ(seq.intrinsics->fx, 525.0);
  ASSERT_TRUE(seq.color_camera);
  EXPECT_EQ(seq.color_camera->intrinsics.width, 800);
  EXPECT_LT((seq.color_camera->color_from_depth.matrix() - TwoCameras().color_from_depth.matrix()).norm(), 1e-6);
  ASSERT_TRUE(seq.ground_truth);
  ASSERT_EQ(seq.ground_truth->size(), 3u);
  EXPECT_LT((seq.ground_truth->world_from_camera[1].matrix() - poses[1].matrix()).norm(), 1e-6);
  // Depth in millimetres (the depth shift), zlib-compressed: the rendered metres to 1 mm.
  const cv::Mat depth = LoadDepthMeters(seq, seq.frames[1]);
  const cv::Mat truth = testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), poses[1]).depth;
  ASSERT_EQ(depth.size(), truth.size());
  double worst = 0;
  cv::minMaxLoc(cv::abs(depth - truth), nullptr, &worst);
  EXPECT_LE(worst, 0.001 + 1e-6);
}

// Colour from the other camera lands on the depth camera's pixels: against the colour the
// depth camera itself would see, closer than that image is to itself moved by one pixel
// (ignoring the 2.5 cm or the 1 degree between the cameras would put it 6-9 pixels off).
TEST(ReadSens, ColourFromAnotherCameraLandsWithinAPixel) {
  const fs::path path = testing::FreshTempDir("sens_align") / "scan.sens";
  testing::SensOptions o = TwoCameras();
  o.color_compression = 1;  // PNG: no JPEG loss in the comparison
  const PoseList poses = Walk(1);
  testing::WriteSyntheticSens(path, testing::SyntheticScene(), poses, o);
  const RgbdSequence seq = ReadSequence(path);
  const cv::Mat aligned = LoadColor(seq, seq.frames[0], cv::Size(640, 480));
  ASSERT_EQ(aligned.size(), cv::Size(640, 480));
  const testing::RenderedFrame truth = testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), poses[0]);
  cv::Mat grey_aligned, grey_truth;
  cv::cvtColor(aligned, grey_aligned, cv::COLOR_BGR2GRAY);
  cv::cvtColor(truth.color, grey_truth, cv::COLOR_BGR2GRAY);
  const cv::Rect inner(20, 20, 600, 440);  // away from the border the colour camera may not see
  auto difference = [&](const cv::Mat& a, const cv::Mat& b) { return cv::mean(cv::abs(a - b))[0]; };
  grey_aligned.convertTo(grey_aligned, CV_32F);
  grey_truth.convertTo(grey_truth, CV_32F);
  const double error = difference(grey_aligned(inner), grey_truth(inner));
  const double one_pixel = difference(grey_truth(inner + cv::Point(1, 0)), grey_truth(inner));
  EXPECT_LT(error, one_pixel) << error << " against " << one_pixel;
  // Grey is resampled the same way.
  const cv::Mat grey = LoadGray(seq, seq.frames[0], cv::Size(640, 480));
  EXPECT_EQ(grey.size(), cv::Size(640, 480));
}

// --align-to color: depth warped into the colour camera (800x600, 2.5 cm and 1 degree away)
// lands where that camera sees the surfaces: the depth edges (a step of 5 cm or more between
// neighbours) within a pixel of the true ones, and the depth within a centimetre where both
// have depth (a footprint carries its pixel's depth: on a slanted surface the colour pixels
// it covers see a few millimetres nearer or farther).
TEST(ReadSens, AlignToColourPutsDepthEdgesOnTheColourCamerasEdges) {
  const fs::path path = testing::FreshTempDir("sens_align_color") / "scan.sens";
  const testing::SensOptions o = TwoCameras();
  const PoseList poses = Walk(1);
  testing::WriteSyntheticSens(path, testing::SyntheticScene(), poses, o);
  IoOptions io;
  io.align_to = AlignTo::kColor;
  const RgbdSequence seq = ReadSequence(path, io);
  ASSERT_TRUE(seq.depth_camera);
  EXPECT_FALSE(seq.color_camera);
  EXPECT_EQ(seq.intrinsics->width, 800);
  const cv::Mat depth = LoadDepthMeters(seq, seq.frames[0]);
  ASSERT_EQ(depth.size(), cv::Size(800, 600));
  EXPECT_EQ(LoadColor(seq, seq.frames[0], depth.size()).size(), cv::Size(800, 600));
  const cv::Mat truth =
      testing::Render(testing::SyntheticScene(), o.color, poses[0] * o.color_from_depth.inverse()).depth;
  auto edges = [](const cv::Mat& z) {
    cv::Mat e(z.size(), CV_8U, cv::Scalar(0));
    for (int y = 1; y < z.rows; ++y) {
      for (int x = 1; x < z.cols; ++x) {
        const float a = z.at<float>(y, x), l = z.at<float>(y, x - 1), u = z.at<float>(y - 1, x);
        if (a > 0 && ((l > 0 && std::abs(a - l) > 0.05f) || (u > 0 && std::abs(a - u) > 0.05f)))
          e.at<uint8_t>(y, x) = 255;
      }
    }
    return e;
  };
  const cv::Mat true_edges = edges(truth), warped_edges = edges(depth);
  ASSERT_GT(cv::countNonZero(true_edges), 100);
  cv::Mat distance;  // to the nearest true edge
  cv::distanceTransform(255 - true_edges, distance, cv::DIST_L2, 3);
  int near = 0, all = 0, agree = 0, both = 0;
  for (int y = 20; y < 580; ++y) {
    for (int x = 20; x < 780; ++x) {
      if (warped_edges.at<uint8_t>(y, x)) ++all, near += distance.at<float>(y, x) <= 1.5f;
      const float a = depth.at<float>(y, x), b = truth.at<float>(y, x);
      if (a > 0 && b > 0) ++both, agree += std::abs(a - b) <= 0.01f;
    }
  }
  ASSERT_GT(all, 100);
  EXPECT_GT(near, 0.95 * all) << near << " of " << all << " depth edges within a pixel of the colour camera's";
  EXPECT_GT(agree, 0.99 * both) << agree << " of " << both;
  EXPECT_GT(both, 0.9 * 760 * 560);  // holes only where the depth camera does not see
}

// A colour camera with lens distortion (a bag's CameraInfo carries it): colour resampled into
// the depth camera through the distortion lands on the depth camera's pixels, as in the test
// above; read as a pinhole camera, it would not.
TEST(ColorCamera, LensDistortionIsAppliedWhenColourIsResampled) {
  const fs::path dir = testing::FreshTempDir("color_distortion");
  const testing::SensOptions o = TwoCameras();
  CameraIntrinsics kc = o.color;
  kc.distortion = {-0.25, 0.08, 0.001, -0.001, 0};
  const Rigid3d pose = Walk(1)[0];
  const testing::RenderedFrame view = testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), pose);
  const cv::Mat pinhole =
      testing::Render(testing::SyntheticScene(), o.color, pose * o.color_from_depth.inverse()).color;
  // The stored, distorted image: each stored pixel from the pinhole pixel the lens moved there.
  cv::Mat map_x(kc.height, kc.width, CV_32F), map_y(kc.height, kc.width, CV_32F);
  for (int y = 0; y < kc.height; ++y) {
    for (int x = 0; x < kc.width; ++x) {
      Eigen::Vector2d undistorted(x, y);
      for (int i = 0; i < 20; ++i) undistorted += Eigen::Vector2d(x, y) - kc.Distort(undistorted.x(), undistorted.y());
      map_x.at<float>(y, x) = static_cast<float>(undistorted.x());
      map_y.at<float>(y, x) = static_cast<float>(undistorted.y());
    }
  }
  cv::Mat stored;
  cv::remap(pinhole, stored, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  cv::Mat depth_mm;
  view.depth.convertTo(depth_mm, CV_16U, 1000.0);
  WritePngFile(dir / "color.png", stored);
  WritePngFile(dir / "depth.png", depth_mm);
  RgbdSequence seq;
  seq.root = dir;
  seq.intrinsics = testing::TestIntrinsics();
  seq.color_camera = ColorCamera{kc, o.color_from_depth};
  RgbdFrame frame;
  frame.color_path = dir / "color.png";
  frame.depth_path = dir / "depth.png";
  seq.frames = {frame};
  cv::Mat grey_truth;
  cv::cvtColor(view.color, grey_truth, cv::COLOR_BGR2GRAY);
  grey_truth.convertTo(grey_truth, CV_32F);
  const cv::Rect inner(40, 40, 560, 400);
  auto error = [&](const RgbdSequence& s) {
    cv::Mat grey;
    cv::cvtColor(LoadColor(s, s.frames[0], cv::Size(640, 480)), grey, cv::COLOR_BGR2GRAY);
    grey.convertTo(grey, CV_32F);
    return cv::mean(cv::abs(grey(inner) - grey_truth(inner)))[0];
  };
  const double one_pixel = cv::mean(cv::abs(grey_truth(inner + cv::Point(1, 0)) - grey_truth(inner)))[0];
  EXPECT_LT(error(seq), one_pixel);
  RgbdSequence as_pinhole = seq;
  as_pinhole.color_camera->intrinsics.distortion = {};
  EXPECT_GT(error(as_pinhole), 2 * one_pixel);
}

TEST(ReadSens, RawColourAndRawDepth) {
  const fs::path path = testing::FreshTempDir("sens_raw") / "scan.sens";
  testing::SensOptions o;
  o.color_compression = 0;
  o.depth_compression = 0;
  o.depth_shift = 5000;
  testing::WriteSyntheticSens(path, testing::SyntheticScene(), Walk(2), o);
  const RgbdSequence seq = ReadSequence(path);
  EXPECT_FALSE(seq.color_camera);  // one camera: colour used as it is
  const cv::Mat color = LoadColor(seq, seq.frames[1], cv::Size(640, 480));
  const testing::RenderedFrame truth =
      testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), Walk(2)[1]);
  EXPECT_EQ(cv::norm(color, truth.color, cv::NORM_INF), 0.0);
  double worst = 0;
  cv::minMaxLoc(cv::abs(LoadDepthMeters(seq, seq.frames[1]) - truth.depth), nullptr, &worst);
  EXPECT_LE(worst, 1.0 / 5000 + 1e-6);
}

// --intrinsics without an image size over a recording: the size from its first depth image,
// read from its place in the recording.
TEST(ReadSens, IntrinsicsOptionTakesTheSizeFromTheRecording) {
  const fs::path path = testing::FreshTempDir("sens_intrinsics") / "scan.sens";
  testing::WriteSyntheticSens(path, testing::SyntheticScene(), Walk(2));
  IoOptions io;
  io.intrinsics = "520,521,319,239";
  const RgbdSequence seq = ReadSequence(path, io);
  ASSERT_TRUE(seq.intrinsics);
  EXPECT_DOUBLE_EQ(seq.intrinsics->fx, 520.0);
  EXPECT_EQ(seq.intrinsics->width, 640);
  EXPECT_EQ(seq.intrinsics->height, 480);
}

TEST(ReadSens, DamagedRecordings) {
  const fs::path dir = testing::FreshTempDir("sens_bad");
  const fs::path good = dir / "good.sens";
  const uint64_t size = testing::WriteSyntheticSens(good, testing::SyntheticScene(), Walk(2));
  const std::string bytes = ReadFileToString(good);
  const fs::path path = dir / "bad.sens";
  auto error = [&](const std::string& content) {
    WriteFileAtomic(path, content);
    return testing::InputErrorMessage([&] { ReadSequence(path); });
  };
  std::string v3 = bytes;
  v3[0] = 3;
  // Not version 4 is not taken for a recording at all.
  EXPECT_EQ(error(v3), path.string() + ": not a dataset folder, .conf, .sens or ROS bag file");
  const size_t header = 4 + 8 + 16 + 4 * 16 * 4;  // version, name, four matrices
  std::string occi = bytes;
  occi[header + 4] = 2;
  EXPECT_EQ(error(occi), path.string() + ": .sens depth compressed as occi_ushort, which fine2coarse does not read");
  std::string colour = bytes;
  colour[header] = 7;
  EXPECT_EQ(error(colour),
            path.string() + ": .sens colour compression 7 is not one fine2coarse reads (0 raw, 1 PNG, 2 JPEG)");
  EXPECT_EQ(error(bytes.substr(0, 100)),
            path.string() + ": .sens cut short in the colour extrinsics (at byte 100 of 100)");
  // Cut inside the second frame's images: the index points past the end.
  const std::string cut = bytes.substr(0, size - 2000);
  EXPECT_NE(error(cut).find(": .sens cut short: frame 1's depth"), std::string::npos) << error(cut);
  std::string frames = bytes;
  const size_t count_at = header + 4 + 4 + 16 + 4;
  frames[count_at + 7] = 1;  // 2^56 frames
  EXPECT_EQ(error(frames), path.string() + fmt::format(": .sens says {} frames, which {} bytes cannot hold",
                                                       (uint64_t{1} << 56) + 2, size));
}

}  // namespace
}  // namespace f2c
