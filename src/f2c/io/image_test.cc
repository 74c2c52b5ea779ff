#include "f2c/io/image.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <functional>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

struct Fixture {
  fs::path dir;
  RgbdSequence seq;
  RgbdFrame frame;
};

Fixture Make(const std::string& name) {
  Fixture f;
  f.dir = testing::FreshTempDir(name);
  f.frame.color_path = f.dir / "c.png";
  f.frame.depth_path = f.dir / "d.png";
  f.seq.intrinsics = testing::TestIntrinsics();
  f.seq.intrinsics_source = "test";
  cv::imwrite(f.frame.color_path.string(), cv::Mat(480, 640, CV_8UC3, cv::Scalar(1, 2, 3)));
  cv::imwrite(f.frame.depth_path.string(), cv::Mat(480, 640, CV_16U, cv::Scalar(2000)));
  return f;
}

TEST(LoadDepthMeters, ScalesAndMarksInvalid) {
  Fixture f = Make("img_ok");
  cv::Mat depth(480, 640, CV_16U, cv::Scalar(2000));
  depth.at<uint16_t>(0, 0) = 0;
  depth.at<uint16_t>(0, 1) = 65535;
  cv::imwrite(f.frame.depth_path.string(), depth);
  f.seq.invalid_depth_values = {0, 65535};
  const cv::Mat m = LoadDepthMeters(f.seq, f.frame);
  EXPECT_FLOAT_EQ(m.at<float>(5, 5), 2.0f);
  EXPECT_EQ(m.at<float>(0, 0), 0.0f);
  EXPECT_EQ(m.at<float>(0, 1), 0.0f);
}

TEST(LoadDepthMeters, EightBitDepthIsAnError) {
  Fixture f = Make("img_8bit");
  cv::imwrite(f.frame.depth_path.string(), cv::Mat(480, 640, CV_8U, cv::Scalar(20)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": depth image is 8-bit; expected 16-bit");
}

TEST(LoadDepthMeters, CorruptAndMissingFiles) {
  Fixture f = Make("img_corrupt");
  WriteFileAtomic(f.frame.depth_path, "\x89PNG\r\n\x1a\n this is not really a png");
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": corrupt PNG: no IHDR chunk after the signature");
  WriteFileAtomic(f.frame.depth_path, "GIF89a, not an image we read");
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": cannot decode image (corrupt or not an image)");
  // A damaged DICOM file: OpenCV's DICOM decoder would abort the program (fuzz_images); only
  // the formats RGB-D recordings use reach OpenCV.
  WriteFileAtomic(f.frame.depth_path, std::string(128, '\xb8') + "DICM" + std::string(64, '\xff'));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": cannot decode image (corrupt or not an image)");
  // ... also when it starts like a PNM image, since OpenCV tries DICOM first.
  WriteFileAtomic(f.frame.depth_path, "P5" + std::string(126, '\xb8') + "DICM" + std::string(64, '\xff'));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": cannot decode image (corrupt or not an image)");
  // A cut-short PNG, and a cut-short JPEG (libjpeg alone would only warn and grey the rest).
  std::vector<uchar> png;
  cv::imencode(".png", cv::Mat(480, 640, CV_16U, cv::Scalar(2000)), png);
  WriteFileAtomic(f.frame.depth_path, std::string(png.begin(), png.begin() + static_cast<long>(png.size() / 2)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": corrupt PNG: the IDAT chunk is cut short");
  std::vector<uchar> jpeg;
  cv::Mat noise(480, 640, CV_8UC3);
  cv::randu(noise, 0, 255);
  cv::imencode(".jpg", noise, jpeg);
  f.frame.color_path = f.dir / "c.jpg";
  WriteFileAtomic(f.frame.color_path, std::string(jpeg.begin(), jpeg.begin() + static_cast<long>(jpeg.size() / 2)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadGray(f.seq, f.frame, cv::Size(640, 480)); }),
            f.frame.color_path.string() + ": corrupt JPEG: Premature end of JPEG file");
  fs::remove(f.frame.depth_path);
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": missing frame image");
}

// Everything fd 2 receives while it lives (libpng and OpenCV write there directly).
class StderrCapture {
 public:
  explicit StderrCapture(const fs::path& file) : file_(file) {
    std::fflush(stderr);
    saved_ = ::dup(2);
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 2);
    ::close(fd);
  }
  std::string Text() {
    std::fflush(stderr);
    std::cerr.flush();
    ::dup2(saved_, 2);
    return ReadFileToString(file_);
  }
  ~StderrCapture() { ::close(saved_); }

 private:
  fs::path file_;
  int saved_ = -1;
};

std::string Cut(const std::vector<uchar>& bytes, double share) {
  return std::string(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() * share));
}

// Damaged images of the kinds libpng and OpenCV decode (palette, 16-bit colour, unknown
// critical chunks, BMP, PNM, TIFF, EXIF JPEG): one error line of ours, nothing of theirs.
TEST(DecodeImageFile, DamagedRareKindsAreOneLineAndNothingOnStderr) {
  const fs::path dir = testing::FreshTempDir("img_rare");
  cv::Mat noise(48, 64, CV_16UC3);
  cv::randu(noise, 0, 65535);
  std::vector<uchar> png16, png8, bmp, pgm, tiff, jpeg;
  cv::imencode(".png", noise, png16);
  cv::Mat noise8;
  noise.convertTo(noise8, CV_8U, 1.0 / 256);
  cv::imencode(".png", noise8, png8);
  cv::imencode(".bmp", noise8, bmp);
  cv::Mat grey;
  cv::cvtColor(noise8, grey, cv::COLOR_BGR2GRAY);
  cv::imencode(".pgm", grey, pgm);
  cv::imencode(".tiff", noise8, tiff);
  cv::imencode(".jpg", noise8, jpeg);
  std::string critical(png8.begin(), png8.begin() + 33);  // signature and IHDR
  critical += std::string("\0\0\0\3ABCDxyz\x22\x6a\x84\x52", 15);
  critical += std::string(png8.begin() + 33, png8.end());
  const std::string exif = std::string(
                               "\xFF\xD8\xFF\xE1\x00\x10"
                               "Exif\0\0",
                               12) +
                           std::string(8, '\0') + std::string(jpeg.begin() + 2, jpeg.end());
  const std::pair<std::string, std::string> cases[] = {
      {Cut(png16, 0.5), "corrupt PNG: the IDAT chunk is cut short"},
      {critical, "corrupt PNG: ABCD: unhandled critical chunk"},
      {Cut(bmp, 0.5), "corrupt image: Unexpected end of input stream"},
      {Cut(pgm, 0.5), "corrupt image: Unexpected end of input stream"},
      {Cut(tiff, 0.5), "cannot decode image (corrupt or not an image)"},
      {exif.substr(0, exif.size() / 2), "corrupt JPEG: Premature end of JPEG file"},
  };
  for (const auto& [bytes, message] : cases) {
    const fs::path path = dir / "frame";
    WriteFileAtomic(path, bytes);
    StderrCapture capture(dir / "stderr.txt");
    const std::string error = testing::InputErrorMessage([&] { DecodeImageFile(path, cv::IMREAD_COLOR); });
    EXPECT_EQ(capture.Text(), "") << message;
    EXPECT_EQ(error, path.string() + ": " + message);
  }
}

// A sequence whose depth is all zero or all an invalid value is an error naming it; one
// frame with depth anywhere (here one the first samples miss) is enough.
TEST(RequireSomeValidDepth, NoFrameWithDepthIsAnError) {
  const fs::path dir = testing::FreshTempDir("img_no_depth");
  RgbdSequence seq;
  seq.root = dir;
  seq.intrinsics = testing::TestIntrinsics();
  seq.invalid_depth_values = {0, 65535};
  for (int k = 0; k < 9; ++k) {
    RgbdFrame frame;
    frame.depth_path = dir / fmt::format("d{}.png", k);
    frame.color_path = dir / "c.png";
    cv::imwrite(frame.depth_path.string(), cv::Mat(480, 640, CV_16U, cv::Scalar(k % 2 == 0 ? 0 : 65535)));
    seq.frames.push_back(frame);
  }
  EXPECT_EQ(testing::InputErrorMessage([&] { RequireSomeValidDepth(seq); }),
            dir.string() +
                ": none of its 9 depth images holds a valid depth (all zero or an invalid value; the first is " +
                (dir / "d0.png").string() + ")");
  cv::Mat one(480, 640, CV_16U, cv::Scalar(0));
  one.at<uint16_t>(100, 100) = 1000;
  cv::imwrite((dir / "d3.png").string(), one);  // samples are frames 0, 2, 4, 6 and 8
  RequireSomeValidDepth(seq);
}

TEST(LoadDepthMeters, SizeMustMatchIntrinsics) {
  Fixture f = Make("img_size_k");
  cv::imwrite(f.frame.depth_path.string(), cv::Mat(240, 320, CV_16U, cv::Scalar(2000)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": depth image is 320x240 but the intrinsics (test) are for 640x480");
}

// Where a stored (distorted) pixel looks in the pinhole model: Distort inverted by fixed-point
// iteration (the test's own inverse; the loaders only ever distort).
Eigen::Vector2d Undistort(const CameraIntrinsics& k, const Eigen::Vector2d& stored) {
  Eigen::Vector2d p = stored;
  for (int i = 0; i < 50; ++i) p += stored - k.Distort(p.x(), p.y());
  return p;
}

// A tilted plane as a camera with TUM fr1's lens stores it (depth along each stored pixel's
// true ray): loaded with the distortion, every pixel back-projects through the pinhole model
// onto the plane; loaded as a pinhole image, the same bytes miss it by centimetres.
TEST(LoadDepthMeters, UndistortsToThePinholeModel) {
  Fixture f = Make("img_undistort");
  const CameraIntrinsics k = ParseIntrinsics("tum-fr1", "test");
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.2, -1).normalized();  // faces the camera
  const double offset = normal.dot(Eigen::Vector3d(0, 0, 2));                  // through (0, 0, 2)
  cv::Mat stored(480, 640, CV_16U);
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) {
      const Eigen::Vector2d p = Undistort(k, {u, v});
      const Eigen::Vector3d ray = k.Unproject(p.x(), p.y(), 1.0);
      stored.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(offset / normal.dot(ray) * 5000));
    }
  }
  cv::imwrite(f.frame.depth_path.string(), stored);
  f.seq.depth_scale = 1.0 / 5000;
  auto worst_off_plane = [&](const CameraIntrinsics& intrinsics, int* valid) {
    f.seq.intrinsics = intrinsics;
    const cv::Mat depth = LoadDepthMeters(f.seq, f.frame);
    double worst = 0;
    *valid = 0;
    for (int v = 0; v < 480; ++v) {
      for (int u = 0; u < 640; ++u) {
        const float z = depth.at<float>(v, u);
        if (z <= 0) continue;
        ++*valid;
        worst = std::max(worst, std::abs(normal.dot(intrinsics.Unproject(u, v, z)) - offset));
      }
    }
    return worst;
  };
  int valid = 0;
  // Nearest neighbour: each pixel takes a ray up to half a pixel off its own (~1.5 mm here).
  EXPECT_LT(worst_off_plane(k, &valid), 0.003);
  EXPECT_GT(valid, 600 * 440);  // only the rim maps outside the stored image
  CameraIntrinsics pinhole = k;
  pinhole.distortion = {};
  EXPECT_GT(worst_off_plane(pinhole, &valid), 0.03);
  EXPECT_EQ(valid, 640 * 480);
}

// Colour goes through the same model: a dot stored where the lens puts pinhole pixel
// (500, 100) comes out there.
TEST(LoadGray, UndistortsLikeTheDepth) {
  Fixture f = Make("img_undistort_gray");
  f.seq.intrinsics = ParseIntrinsics("tum-fr1", "test");
  const Eigen::Vector2d at = f.seq.intrinsics->Distort(500, 100);
  cv::Mat color(480, 640, CV_8UC3, cv::Scalar(0, 0, 0));
  cv::circle(color, cv::Point(static_cast<int>(std::lround(at.x())), static_cast<int>(std::lround(at.y()))), 2,
             cv::Scalar(255, 255, 255), cv::FILLED);
  cv::imwrite(f.frame.color_path.string(), color);
  EXPECT_GT(std::abs(at.x() - 500) + std::abs(at.y() - 100), 10);  // the lens moves it visibly
  const cv::Mat gray = LoadGray(f.seq, f.frame, cv::Size(640, 480));
  cv::Point brightest;
  cv::minMaxLoc(gray, nullptr, nullptr, nullptr, &brightest);
  EXPECT_LE(std::abs(brightest.x - 500), 1);
  EXPECT_LE(std::abs(brightest.y - 100), 1);
}

TEST(LoadColor, SizeMustMatchDepth) {
  Fixture f = Make("img_size_c");
  cv::imwrite(f.frame.color_path.string(), cv::Mat(240, 320, CV_8UC3, cv::Scalar(0)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadColor(f.seq, f.frame, cv::Size(640, 480)); }),
            f.frame.color_path.string() + ": colour image is 320x240 but its depth image d.png is 640x480");
}

TEST(DecodeDepthValue, Sun3dRotation) {
  // 1234 mm rotated left by 3 bits is 9872; 9000 mm wraps bits into the low end.
  EXPECT_EQ(DecodeDepthValue(9872, DepthEncoding::kSun3dBitRotated), 1234);
  const uint16_t v = static_cast<uint16_t>((9000 << 3) | (9000 >> 13));
  EXPECT_EQ(DecodeDepthValue(v, DepthEncoding::kSun3dBitRotated), 9000);
  EXPECT_EQ(DecodeDepthValue(9872, DepthEncoding::kPlain), 9872);
}

}  // namespace
}  // namespace f2c
