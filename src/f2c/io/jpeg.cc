#include "f2c/io/jpeg.h"

#include <fmt/format.h>

#include <turbojpeg.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <opencv2/core.hpp>
#include <memory>

namespace f2c {
namespace {

// The EXIF orientation (1-8) of the first APP1 segment that carries EXIF data; 1 (as stored)
// when there is none or it cannot be read. OpenCV turns IMREAD_COLOR and IMREAD_GRAYSCALE
// images by it, and so do we.
int ExifOrientation(const uint8_t* data, size_t size) {
  size_t pos = 2;  // after SOI
  while (pos + 4 <= size && data[pos] == 0xFF) {
    const uint8_t marker = data[pos + 1];
    if (marker == 0xDA || marker == 0xD9) return 1;  // start of scan, end of image
    const size_t length = static_cast<size_t>(data[pos + 2]) << 8 | data[pos + 3];
    if (marker == 0xE1 && length >= 8 && pos + 10 <= size && std::memcmp(data + pos + 4, "Exif\0\0", 6) == 0) {
      // A TIFF structure: byte order, 42, the offset of IFD0, then 12-byte entries.
      const uint8_t* tiff = data + pos + 10;
      const size_t n = std::min(size - (pos + 10), length - 8);
      if (n < 8 || !(tiff[0] == tiff[1] && (tiff[0] == 'I' || tiff[0] == 'M'))) return 1;
      const bool little = tiff[0] == 'I';
      auto u16 = [&](size_t at) { return little ? tiff[at] | tiff[at + 1] << 8 : tiff[at] << 8 | tiff[at + 1]; };
      auto u32 = [&](size_t at) {
        return little ? uint32_t{tiff[at]} | uint32_t{tiff[at + 1]} << 8 | uint32_t{tiff[at + 2]} << 16 |
                            uint32_t{tiff[at + 3]} << 24
                      : uint32_t{tiff[at]} << 24 | uint32_t{tiff[at + 1]} << 16 | uint32_t{tiff[at + 2]} << 8 |
                            uint32_t{tiff[at + 3]};
      };
      const size_t ifd = u32(4);
      if (ifd + 2 > n) return 1;
      const size_t entries = u16(ifd);
      for (size_t e = 0; e < entries && ifd + 2 + 12 * (e + 1) <= n; ++e) {
        const size_t at = ifd + 2 + 12 * e;
        if (u16(at) == 0x0112) {
          const int orientation = u16(at + 8);
          return orientation >= 1 && orientation <= 8 ? orientation : 1;
        }
      }
      return 1;
    }
    pos += 2 + length;
  }
  return 1;
}

// Turns a decoded image as EXIF orientation `o` says (OpenCV's ApplyExifOrientation).
void ApplyOrientation(int o, cv::Mat* image) {
  if (o >= 5) cv::transpose(*image, *image);
  if (o == 2 || o == 6) cv::flip(*image, *image, 1);   // horizontally
  if (o == 3 || o == 7) cv::flip(*image, *image, -1);  // both ways
  if (o == 4 || o == 8) cv::flip(*image, *image, 0);   // vertically
}

// CMYK (as libjpeg hands out Adobe's inverted CMYK and YCCK) to BGR or grey, with OpenCV's
// integer formulas so that a CMYK frame reads the same as OpenCV read it.
void CmykToBgrOrGrey(const uint8_t* cmyk, int pixels, bool grey, uint8_t* out) {
  for (int i = 0; i < pixels; ++i, cmyk += 4) {
    const int k = cmyk[3];
    const int r = k - ((255 - cmyk[0]) * k >> 8);
    const int g = k - ((255 - cmyk[1]) * k >> 8);
    const int b = k - ((255 - cmyk[2]) * k >> 8);
    if (grey) {
      // ITU-R BT.601 weights in 14-bit fixed point, rounded.
      out[i] = static_cast<uint8_t>((b * 1868 + g * 9617 + r * 4899 + (1 << 13)) >> 14);
    } else {
      out[3 * i] = static_cast<uint8_t>(b);
      out[3 * i + 1] = static_cast<uint8_t>(g);
      out[3 * i + 2] = static_cast<uint8_t>(r);
    }
  }
}

}  // namespace

DecodeStatus DecodeJpeg(std::string_view bytes, bool grey, cv::Mat* out, std::string* problem) {
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const size_t size = bytes.size();
  if (size < 4 || data[0] != 0xFF || data[1] != 0xD8) return DecodeStatus::kNotHandled;
  thread_local std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitDecompress(), tjDestroy);
  if (!handle) return DecodeStatus::kNotHandled;
  int width = 0, height = 0, subsampling = 0, colorspace = 0;
  if (tjDecompressHeader3(handle.get(), data, static_cast<unsigned long>(size), &width, &height, &subsampling,
                          &colorspace) != 0) {
    return DecodeStatus::kNotHandled;
  }
  const bool cmyk = colorspace == TJCS_CMYK || colorspace == TJCS_YCCK;
  if (colorspace != TJCS_YCbCr && colorspace != TJCS_RGB && colorspace != TJCS_GRAY && !cmyk) {
    return DecodeStatus::kNotHandled;
  }
  if (width <= 0 || height <= 0) return DecodeStatus::kNotHandled;
  // Larger than any depth camera's frame: refused before anything is allocated.
  if (int64_t{width} * height > (int64_t{1} << 25)) {
    if (problem)
      *problem = fmt::format("JPEG of {} x {} pixels: over the 32-megapixel limit for RGB-D frames", width, height);
    return DecodeStatus::kCorrupt;
  }
  cv::Mat image(height, width, grey ? CV_8UC1 : CV_8UC3);
  cv::Mat decoded = cmyk ? cv::Mat(height, width, CV_8UC4) : image;
  const int format = cmyk ? TJPF_CMYK : grey ? TJPF_GRAY : TJPF_BGR;
  // A warning (a cut-short or damaged stream decodes partly) counts as damage.
  if (tjDecompress2(handle.get(), data, static_cast<unsigned long>(size), decoded.data, width,
                    static_cast<int>(decoded.step[0]), height, format, TJFLAG_STOPONWARNING) != 0) {
    if (problem) *problem = std::string("corrupt JPEG: ") + tjGetErrorStr2(handle.get());
    return DecodeStatus::kCorrupt;
  }
  if (cmyk) CmykToBgrOrGrey(decoded.data, width * height, grey, image.data);
  ApplyOrientation(ExifOrientation(data, size), &image);
  *out = std::move(image);
  return DecodeStatus::kDecoded;
}

}  // namespace f2c
