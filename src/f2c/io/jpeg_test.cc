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

TEST(DecodeJpeg, LeavesExifToOpenCvAndSaysWhenCutShort) {
  const std::string jpeg = Encode(JpegTestImage(CV_8UC3, 9), {});
  cv::Mat out;
  ASSERT_EQ(DecodeJpeg(jpeg, false, &out), DecodeStatus::kDecoded);
  const cv::Mat decoded = out;
  // An EXIF segment (OpenCV would apply its orientation): right after SOI.
  const std::string exif = std::string(
                               "\xFF\xE1\x00\x10"
                               "Exif\0\0",
                               10) +
                           std::string(8, '\0');
  EXPECT_EQ(DecodeJpeg(jpeg.substr(0, 2) + exif + jpeg.substr(2), false, &out), DecodeStatus::kNotHandled);
  EXPECT_EQ(DecodeJpeg("\x89PNG\r\n\x1a\n", true, &out), DecodeStatus::kNotHandled);
  // Cut short: libjpeg alone would fill the rest with grey and only warn.
  std::string problem;
  EXPECT_EQ(DecodeJpeg(jpeg.substr(0, jpeg.size() / 2), true, &out, &problem), DecodeStatus::kCorrupt);
  EXPECT_EQ(problem, "corrupt JPEG: Premature end of JPEG file");
  EXPECT_EQ(out.data, decoded.data);  // untouched by the failures
}

}  // namespace
}  // namespace f2c
