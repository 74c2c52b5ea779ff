#pragma once
// Images written by fine2coarse itself (the simulator's frames, register_frames' frames,
// feature and mesh pictures, the report's JPEGs): PNG through libdeflate and JPEG through
// TurboJPEG, the libraries its readers use. OpenCV's imgcodecs is not linked for this: it
// brings GDAL and about 120 other libraries, whose loading cost every process 0.15 s at
// start (0.4 s under AddressSanitizer), more than most tests take (docs/testing.md).

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace f2c {

// A PNG of an 8-bit grey (CV_8UC1), BGR (CV_8UC3, stored as RGB), BGRA (CV_8UC4, stored as
// RGBA) or 16-bit grey (CV_16UC1) image; each row with the filter whose output has the least
// absolute sum (libpng's heuristic). InputError for any other type.
std::string EncodePng(const cv::Mat& image);

// A baseline JPEG of an 8-bit BGR or grey image at `quality` (1-100; 4:2:0 for colour).
std::string EncodeJpeg(const cv::Mat& image, int quality);

// EncodePng written to `path` atomically (WriteFileAtomic: never a half-written image).
void WritePngFile(const std::filesystem::path& path, const cv::Mat& image);

}  // namespace f2c
