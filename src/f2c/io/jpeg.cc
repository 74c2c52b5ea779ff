#include "f2c/io/jpeg.h"

#include <turbojpeg.h>

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

bool DecodeJpegBgr(std::string_view bytes, cv::Mat* out) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const size_t size = bytes.size();
  if (size < 4 || data[0] != 0xFF || data[1] != 0xD8 || HasExif(data, size)) return false;
  thread_local std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitDecompress(), tjDestroy);
  if (!handle) return false;
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle.get(), data, static_cast<unsigned long>(size), &width, &height, &subsampling,
                          &colorspace) != 0) {
    return false;
  }
  if (colorspace != TJCS_YCbCr && colorspace != TJCS_RGB && colorspace != TJCS_GRAY) return false;
  if (width <= 0 || height <= 0 || width > (1 << 15) || height > (1 << 15)) return false;
  cv::Mat image(height, width, CV_8UC3);
  // Any warning (a truncated or corrupt stream decodes partly) counts as failure.
  if (tjDecompress2(handle.get(), data, static_cast<unsigned long>(size), image.data, width, static_cast<int>(image.step[0]),
                    height, TJPF_BGR, TJFLAG_STOPONWARNING) != 0) {
    return false;
  }
  *out = std::move(image);
  return true;
}

}  // namespace f2c
