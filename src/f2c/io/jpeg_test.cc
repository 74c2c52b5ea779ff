#include "f2c/io/jpeg.h"

#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

#include "f2c/util/file.h"

namespace f2c {
namespace {

cv::Mat JpegTestImage(int type, uint32_t seed) {
  cv::Mat image(96, 128, type);
  std::mt19937 rng(seed);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols * image.channels(); ++x) {
      image.ptr<uint8_t>(y)[x] = static_cast<uint8_t>((x * 3 + y * 5) % 200 + rng() % 40);
    }
  }
  return image;
}

std::string Encode(const cv::Mat& image, const std::vector<int>& params) {
  std::vector<uchar> buffer;
  EXPECT_TRUE(cv::imencode(".jpg", image, buffer, params));
  return std::string(buffer.begin(), buffer.end());
}

cv::Mat OpenCv(const std::string& jpeg) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(jpeg.size()), CV_8U, const_cast<char*>(jpeg.data())),
                      cv::IMREAD_COLOR);
}

void ExpectSameAsOpenCv(const std::string& jpeg, const std::string& what) {
  cv::Mat ours;
  ASSERT_EQ(DecodeJpeg(jpeg, false, &ours), DecodeStatus::kDecoded) << what;
  const cv::Mat theirs = OpenCv(jpeg);
  ASSERT_EQ(ours.type(), theirs.type()) << what;
  ASSERT_EQ(ours.size(), theirs.size()) << what;
  EXPECT_EQ(cv::norm(ours, theirs, cv::NORM_INF), 0.0) << what;
  // And grey, as IMREAD_GRAYSCALE.
  cv::Mat grey;
  ASSERT_EQ(DecodeJpeg(jpeg, true, &grey), DecodeStatus::kDecoded) << what;
  const cv::Mat their_grey = cv::imdecode(
      cv::Mat(1, static_cast<int>(jpeg.size()), CV_8U, const_cast<char*>(jpeg.data())), cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(grey.type(), their_grey.type()) << what;
  EXPECT_EQ(cv::norm(grey, their_grey, cv::NORM_INF), 0.0) << what;
}

// TurboJPEG's encoder, for the chroma subsamplings OpenCV 4.6's encoder cannot choose.
std::string EncodeTurbo(const cv::Mat& bgr, int subsampling, int quality) {
  tjhandle h = tjInitCompress();
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  EXPECT_EQ(tjCompress2(h, bgr.data, bgr.cols, static_cast<int>(bgr.step[0]), bgr.rows, TJPF_BGR, &buffer, &size,
                        subsampling, quality, 0),
            0);
  std::string jpeg(reinterpret_cast<char*>(buffer), size);
  tjFree(buffer);
  tjDestroy(h);
  return jpeg;
}

TEST(DecodeJpeg, EqualsOpenCvForEverySubsamplingQualityAndGrey) {
  for (int sampling : {TJSAMP_444, TJSAMP_422, TJSAMP_420, TJSAMP_411, TJSAMP_GRAY}) {
    for (int quality : {50, 95}) {
      ExpectSameAsOpenCv(EncodeTurbo(JpegTestImage(CV_8UC3, quality + sampling), sampling, quality),
                         "sampling " + std::to_string(sampling) + " quality " + std::to_string(quality));
    }
  }
  for (int progressive : {0, 1}) {
    ExpectSameAsOpenCv(Encode(JpegTestImage(CV_8UC3, 5), {cv::IMWRITE_JPEG_PROGRESSIVE, progressive}), "progressive");
  }
  ExpectSameAsOpenCv(Encode(JpegTestImage(CV_8UC1, 3), {}), "grey");
}

TEST(DecodeJpeg, EqualsOpenCvOnRealFrames) {
  const std::filesystem::path rgb = std::filesystem::path(F2C_SHARED_DATA_DIR) / "tum_fr1_xyz_15hz" / "rgb";
  if (!std::filesystem::is_directory(rgb)) GTEST_SKIP() << rgb << " absent";
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(rgb)) {
    if (n++ == 10) break;
    ExpectSameAsOpenCv(ReadFileToString(entry.path()), entry.path().string());
  }
}

// An EXIF segment right after SOI whose IFD0 holds the orientation tag.
std::string WithExifOrientation(const std::string& jpeg, int orientation, bool little_endian) {
  std::string tiff = little_endian ? std::string("II\x2a\0\x08\0\0\0", 8) : std::string("MM\0\x2a\0\0\0\x08", 8);
  auto u16 = [&](int v) {
    return little_endian ? std::string{static_cast<char>(v & 255), static_cast<char>(v >> 8)}
                         : std::string{static_cast<char>(v >> 8), static_cast<char>(v & 255)};
  };
  tiff += u16(1);  // one entry
  tiff += u16(0x0112) + u16(3) + (little_endian ? std::string("\1\0\0\0", 4) : std::string("\0\0\0\1", 4));
  tiff += u16(orientation) + u16(0);
  tiff += std::string(4, '\0');  // no next IFD
  const std::string body = std::string("Exif\0\0", 6) + tiff;
  const size_t length = body.size() + 2;
  const std::string app1 = std::string("\xFF\xE1") + static_cast<char>(length >> 8) + static_cast<char>(length & 255);
  return jpeg.substr(0, 2) + app1 + body + jpeg.substr(2);
}

TEST(DecodeJpeg, TurnsByExifOrientationAsOpenCvAndSaysWhenCutShort) {
  const std::string jpeg = Encode(JpegTestImage(CV_8UC3, 9), {});
  cv::Mat out;
  ASSERT_EQ(DecodeJpeg(jpeg, false, &out), DecodeStatus::kDecoded);
  const cv::Mat decoded = out;
  for (int orientation = 1; orientation <= 8; ++orientation) {
    for (bool little : {true, false}) {
      const std::string turned = WithExifOrientation(jpeg, orientation, little);
      ExpectSameAsOpenCv(turned, "orientation " + std::to_string(orientation));
      cv::Mat image;
      ASSERT_EQ(DecodeJpeg(turned, false, &image), DecodeStatus::kDecoded);
      EXPECT_EQ(image.rows, orientation >= 5 ? decoded.cols : decoded.rows) << orientation;
    }
  }
  EXPECT_EQ(DecodeJpeg("\x89PNG\r\n\x1a\n", true, &out), DecodeStatus::kNotHandled);
  // Cut short: libjpeg alone would fill the rest with grey and only warn (OpenCV reads an
  // EXIF JPEG cut short so, without a word).
  std::string problem;
  EXPECT_EQ(DecodeJpeg(jpeg.substr(0, jpeg.size() / 2), true, &out, &problem), DecodeStatus::kCorrupt);
  EXPECT_EQ(problem, "corrupt JPEG: Premature end of JPEG file");
  const std::string exif = WithExifOrientation(jpeg, 6, true);
  EXPECT_EQ(DecodeJpeg(exif.substr(0, exif.size() / 2), false, &out, &problem), DecodeStatus::kCorrupt);
  EXPECT_EQ(out.data, decoded.data);  // untouched by the failures
}

// CMYK (YCCK as TurboJPEG writes it from CMYK pixels): decoded like OpenCV, and a file cut
// short is damage like any other JPEG (OpenCV would hand back the grey-filled rest).
TEST(DecodeJpeg, CmykEqualsOpenCvAndSaysWhenCutShort) {
  const cv::Mat cmyk = JpegTestImage(CV_8UC4, 11);
  tjhandle h = tjInitCompress();
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  ASSERT_EQ(tjCompress2(h, cmyk.data, cmyk.cols, static_cast<int>(cmyk.step[0]), cmyk.rows, TJPF_CMYK, &buffer, &size,
                        TJSAMP_444, 90, 0),
            0);
  const std::string jpeg(reinterpret_cast<char*>(buffer), size);
  tjFree(buffer);
  tjDestroy(h);
  ExpectSameAsOpenCv(jpeg, "cmyk");
  cv::Mat out;
  std::string problem;
  EXPECT_EQ(DecodeJpeg(jpeg.substr(0, jpeg.size() * 2 / 3), false, &out, &problem), DecodeStatus::kCorrupt);
  EXPECT_EQ(problem, "corrupt JPEG: Premature end of JPEG file");
}

}  // namespace
}  // namespace f2c
