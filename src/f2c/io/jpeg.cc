#include "f2c/io/jpeg.h"

#include <fmt/format.h>

#include <turbojpeg.h>

#include <cstdint>
#include <cstring>
#include <memory>

namespace f2c {
namespace {

// Whether an APP1 segment carries EXIF data (its orientation tag is OpenCV's business).
bool HasExif(const uint8_t* data, size_t size) {
  size_t pos = 2;  // after SOI
  while (pos + 4 <= size && data[pos] == 0xFF) {
    const uint8_t marker = data[pos + 1];
    if (marker == 0xDA || marker == 0xD9) return false;  // start of scan, end of image
    const size_t length = static_cast<size_t>(data[pos + 2]) << 8 | data[pos + 3];
    if (marker == 0xE1 && length >= 8 && pos + 10 <= size && std::memcmp(data + pos + 4, "Exif", 4) == 0) return true;
    pos += 2 + length;
  }
  return false;
}

}  // namespace

DecodeStatus DecodeJpeg(std::string_view bytes, bool grey, cv::Mat* out, std::string* problem) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const size_t size = bytes.size();
  if (size < 4 || data[0] != 0xFF || data[1] != 0xD8 || HasExif(data, size)) return DecodeStatus::kNotHandled;
  thread_local std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitDecompress(), tjDestroy);
  if (!handle) return DecodeStatus::kNotHandled;
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle.get(), data, static_cast<unsigned long>(size), &width, &height, &subsampling,
                          &colorspace) != 0) {
    return DecodeStatus::kNotHandled;
  }
  if (colorspace != TJCS_YCbCr && colorspace != TJCS_RGB && colorspace != TJCS_GRAY) return DecodeStatus::kNotHandled;
  if (width <= 0 || height <= 0) return DecodeStatus::kNotHandled;
  // Larger than any depth camera's frame: refused before anything is allocated.
  if (int64_t{width} * height > (int64_t{1} << 25)) {
    if (problem)
      *problem = fmt::format("JPEG of {} x {} pixels: over the 32-megapixel limit for RGB-D frames", width, height);
    return DecodeStatus::kCorrupt;
  }
  cv::Mat image(height, width, grey ? CV_8UC1 : CV_8UC3);
  // A warning (a cut-short or damaged stream decodes partly) counts as damage.
  if (tjDecompress2(handle.get(), data, static_cast<unsigned long>(size), image.data, width,
                    static_cast<int>(image.step[0]), height, grey ? TJPF_GRAY : TJPF_BGR, TJFLAG_STOPONWARNING) != 0) {
    if (problem) *problem = std::string("corrupt JPEG: ") + tjGetErrorStr2(handle.get());
    return DecodeStatus::kCorrupt;
  }
  *out = std::move(image);
  return DecodeStatus::kDecoded;
}

}  // namespace f2c
