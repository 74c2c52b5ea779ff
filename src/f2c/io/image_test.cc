#include "f2c/io/image.h"

#include <gtest/gtest.h>

#include <functional>
#include <opencv2/imgcodecs.hpp>

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
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadGray(f.frame, cv::Size(640, 480)); }),
            f.frame.color_path.string() + ": corrupt JPEG: Premature end of JPEG file");
  fs::remove(f.frame.depth_path);
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }), f.frame.depth_path.string() + ": missing frame image");
}

TEST(LoadDepthMeters, SizeMustMatchIntrinsics) {
  Fixture f = Make("img_size_k");
  cv::imwrite(f.frame.depth_path.string(), cv::Mat(240, 320, CV_16U, cv::Scalar(2000)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadDepthMeters(f.seq, f.frame); }),
            f.frame.depth_path.string() + ": depth image is 320x240 but the intrinsics (test) are for 640x480");
}

TEST(LoadColor, SizeMustMatchDepth) {
  Fixture f = Make("img_size_c");
  cv::imwrite(f.frame.color_path.string(), cv::Mat(240, 320, CV_8UC3, cv::Scalar(0)));
  EXPECT_EQ(testing::InputErrorMessage([&] { LoadColor(f.frame, cv::Size(640, 480)); }),
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
