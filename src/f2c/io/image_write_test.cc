#include "f2c/io/image_write.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "f2c/io/image.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

// Ramps with noise (every PNG filter wins somewhere) of the given type.
cv::Mat RampImage(int type, uint32_t seed) {
  cv::Mat image(41, 67, type);
  std::mt19937 rng(seed);
  const int channels = image.channels();
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      for (int c = 0; c < channels; ++c) {
        const int v = (x * 5 + y * 3 + c * 50) % 256 + static_cast<int>(rng() % 5);
        if (image.depth() == CV_16U) {
          image.ptr<uint16_t>(y)[x * channels + c] = static_cast<uint16_t>(v * 251 + rng() % 300);
        } else {
          image.ptr<uint8_t>(y)[x * channels + c] = static_cast<uint8_t>(v);
        }
      }
    }
  }
  return image;
}

bool Same(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0;
}

cv::Mat OpenCvDecode(const std::string& bytes, int flags) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data())), flags);
}

// Our PNGs read back exactly, by libpng (through OpenCV) and by our own decoder.
TEST(EncodePng, EveryWrittenTypeReadsBackExactly) {
  const fs::path dir = testing::FreshTempDir("encode_png");
  for (int type : {CV_8UC1, CV_8UC3, CV_8UC4, CV_16UC1}) {
    const cv::Mat image = RampImage(type, 3 + type);
    const std::string png = EncodePng(image);
    EXPECT_TRUE(Same(OpenCvDecode(png, cv::IMREAD_UNCHANGED), image)) << "type " << type;
    if (type == CV_8UC4) continue;  // alpha: our decoder leaves it to OpenCV
    WritePngFile(dir / "image.png", image);
    EXPECT_EQ(ReadFileToString(dir / "image.png"), png);
    EXPECT_TRUE(Same(DecodeImageFile(dir / "image.png", cv::IMREAD_UNCHANGED), image)) << "type " << type;
  }
  EXPECT_EQ(testing::InputErrorMessage([] { EncodePng(cv::Mat(4, 4, CV_32F)); }),
            "PNG: only 8-bit grey, BGR or BGRA and 16-bit grey images are written");
}

// A JPEG at quality 95 of a smooth image comes back within a few grey levels.
TEST(EncodeJpeg, ReadsBackCloseToTheImage) {
  for (int type : {CV_8UC3, CV_8UC1}) {
    cv::Mat image(48, 64, type);
    for (int y = 0; y < image.rows; ++y) {
      for (int x = 0; x < image.cols; ++x) {
        for (int c = 0; c < image.channels(); ++c)
          image.ptr<uint8_t>(y)[x * image.channels() + c] = (2 * x + y + 60 * c) % 256;
      }
    }
    const cv::Mat back = OpenCvDecode(EncodeJpeg(image, 95), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.type(), image.type());
    cv::Mat difference;
    cv::absdiff(back, image, difference);
    EXPECT_LT(cv::mean(difference)[0], 3.0) << "type " << type;
  }
}

// Kinds our own decoders leave to OpenCV (BMP, PNM, a PNG with alpha) are decoded by OpenCV's
// decoders, loaded at first use from their own library.
TEST(DecodeImageFile, RarerKindsReachOpenCvsDecoders) {
  const fs::path dir = testing::FreshTempDir("decode_rarer");
  const cv::Mat colour = RampImage(CV_8UC3, 1), depth = RampImage(CV_16UC1, 2);
  ASSERT_TRUE(cv::imwrite((dir / "c.bmp").string(), colour));
  ASSERT_TRUE(cv::imwrite((dir / "d.pgm").string(), depth));
  WritePngFile(dir / "a.png", RampImage(CV_8UC4, 4));
  EXPECT_TRUE(Same(DecodeImageFile(dir / "c.bmp", cv::IMREAD_COLOR), colour));
  EXPECT_TRUE(Same(DecodeImageFile(dir / "d.pgm", cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR), depth));
  cv::Mat bgr;
  cv::cvtColor(RampImage(CV_8UC4, 4), bgr, cv::COLOR_BGRA2BGR);
  EXPECT_TRUE(Same(DecodeImageFile(dir / "a.png", cv::IMREAD_COLOR), bgr));
}

}  // namespace
}  // namespace f2c
