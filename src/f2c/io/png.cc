#include "f2c/io/png.h"

#include <fmt/format.h>
#include <libdeflate.h>

#include <cctype>
#include <string>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace f2c {
namespace {

uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

bool Is(const uint8_t* type, const char* name) { return std::memcmp(type, name, 4) == 0; }

// Chunks that change what libpng (and so OpenCV) returns: a palette, transparency turned
// into alpha, gamma and colour spaces that its grey conversion may honour. With any of them
// the fast path steps aside rather than risk a different answer.
bool ChangesPixels(const uint8_t* type) {
  for (const char* name : {"PLTE", "tRNS", "gAMA", "sRGB", "iCCP", "cHRM", "sBIT"}) {
    if (Is(type, name)) return true;
  }
  return false;
}

struct Header {
  uint32_t width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
};

// The PNG filters (PNG spec, section 9), undone in place on one row given the previous
// (unfiltered) row; BPP is the bytes per pixel, the distance to the "left" byte.
template <int BPP>
bool Unfilter(int filter, uint8_t* row, const uint8_t* above, size_t n) {
  switch (filter) {
    case 0:
      return true;
    case 1:
      for (size_t i = BPP; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + row[i - BPP]);
      return true;
    case 2:
      for (size_t i = 0; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + above[i]);
      return true;
    case 3:
      for (size_t i = 0; i < BPP && i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + (above[i] >> 1));
      for (size_t i = BPP; i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + ((row[i - BPP] + above[i]) >> 1));
      return true;
    case 4:
      for (size_t i = 0; i < BPP && i < n; ++i) row[i] = static_cast<uint8_t>(row[i] + above[i]);
      for (size_t i = BPP; i < n; ++i) {
        const int a = row[i - BPP], b = above[i], c = above[i - BPP];
        const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
        const int predictor = pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
        row[i] = static_cast<uint8_t>(row[i] + predictor);
      }
      return true;
    default:
      return false;
  }
}

bool UnfilterRow(int bpp, int filter, uint8_t* row, const uint8_t* above, size_t n) {
  switch (bpp) {
    case 1:
      return Unfilter<1>(filter, row, above, n);
    case 2:
      return Unfilter<2>(filter, row, above, n);
    default:
      return Unfilter<3>(filter, row, above, n);
  }
}

// libpng's RGB to grey (png_set_rgb_to_gray with OpenCV's weights 0.299 and 0.587, no
// gamma): 15-bit fixed-point weights, truncated, and grey pixels passed through unchanged.
constexpr uint32_t kRed = 29900u * 32768u / 100000u;    // 9797
constexpr uint32_t kGreen = 58700u * 32768u / 100000u;  // 19234
constexpr uint32_t kBlue = 32768u - kRed - kGreen;      // 3737

void RgbRowTo(PngRequest request, const uint8_t* rgb, uint8_t* out, uint32_t width) {
  if (request == PngRequest::kGray) {
    for (uint32_t x = 0; x < width; ++x, rgb += 3) {
      const uint32_t r = rgb[0], g = rgb[1], b = rgb[2];
      out[x] =
          r == g && r == b ? static_cast<uint8_t>(r) : static_cast<uint8_t>((kRed * r + kGreen * g + kBlue * b) >> 15);
    }
  } else {
    for (uint32_t x = 0; x < width; ++x, rgb += 3, out += 3) {
      out[0] = rgb[2];
      out[1] = rgb[1];
      out[2] = rgb[0];
    }
  }
}

void GreyRowTo(PngRequest request, const Header& h, const uint8_t* in, uint8_t* out) {
  if (h.bit_depth == 16) {
    auto* o = reinterpret_cast<uint16_t*>(out);
    for (uint32_t x = 0; x < h.width; ++x) o[x] = static_cast<uint16_t>((in[2 * x] << 8) | in[2 * x + 1]);
  } else if (request == PngRequest::kBgr) {
    for (uint32_t x = 0; x < h.width; ++x) out[3 * x] = out[3 * x + 1] = out[3 * x + 2] = in[x];
  } else {
    std::memcpy(out, in, h.width);
  }
}

// A chunk's four-letter type for messages (printable letters, or its bytes in hex).
std::string ChunkName(const uint8_t* type) {
  std::string name;
  for (int i = 0; i < 4; ++i) {
    if (!std::isalpha(type[i])) return fmt::format("{:02x}{:02x}{:02x}{:02x}", type[0], type[1], type[2], type[3]);
    name += static_cast<char>(type[i]);
  }
  return name;
}

}  // namespace

DecodeStatus DecodePng(std::string_view bytes, PngRequest request, cv::Mat* out, std::string* problem) {
  auto corrupt = [&](const std::string& what) {
    if (problem) *problem = what;
    return DecodeStatus::kCorrupt;
  };
  constexpr DecodeStatus kNotHandled = DecodeStatus::kNotHandled;
  static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const auto* data = reinterpret_cast<const uint8_t*>(bytes.data());
  const size_t size = bytes.size();
  if (size < 8 || std::memcmp(data, kSignature, 8) != 0) return kNotHandled;

  // Chunks: length, type, data, CRC over type and data. IHDR first, IEND last.
  Header h;
  std::vector<uint8_t> stream;
  bool ended = false;
  for (size_t pos = 8; pos + 12 <= size && !ended;) {
    const uint32_t length = BigEndian32(data + pos);
    const uint8_t* type = data + pos + 4;
    const bool first = pos == 8;
    if (first != Is(type, "IHDR")) {
      return corrupt(first ? "corrupt PNG: no IHDR chunk after the signature" : "corrupt PNG: a second IHDR chunk");
    }
    if (length > size - pos - 12)
      return corrupt(fmt::format("corrupt PNG: the {} chunk is cut short", ChunkName(type)));
    const uint8_t* body = type + 4;
    if (libdeflate_crc32(0, type, length + 4) != BigEndian32(body + length)) {
      // Damage in the image's own chunks is an error; libpng skips a damaged ancillary one.
      if ((type[0] & 0x20) == 0)
        return corrupt(fmt::format("corrupt PNG: bad checksum in the {} chunk", ChunkName(type)));
      return kNotHandled;
    }
    if (Is(type, "IHDR")) {
      if (length != 13) return corrupt("corrupt PNG: IHDR chunk of the wrong size");
      h.width = BigEndian32(body);
      h.height = BigEndian32(body + 4);
      // Larger than any depth camera's frame: refused from the header, before anything else.
      if (uint64_t{h.width} * h.height > (uint64_t{1} << 25)) {
        return corrupt(
            fmt::format("PNG of {} x {} pixels: over the 32-megapixel limit for RGB-D frames", h.width, h.height));
      }
      h.bit_depth = body[8];
      h.color_type = body[9];
      if (body[10] != 0 || body[11] != 0 || body[12] != 0) return kNotHandled;  // compression, filter, interlace
    } else if (Is(type, "IDAT")) {
      stream.insert(stream.end(), body, body + length);
    } else if (Is(type, "IEND")) {
      ended = true;
    } else if (ChangesPixels(type) || (type[0] & 0x20) == 0) {
      return kNotHandled;  // a pixel-changing chunk, or a critical chunk this path does not know
    }
    pos += 12 + size_t{length};
  }
  if (!ended) return corrupt("corrupt PNG: no IEND chunk (cut short?)");
  if (stream.empty()) return corrupt("corrupt PNG: no image data");
  const bool grey = h.color_type == 0 && (h.bit_depth == 8 || h.bit_depth == 16);
  const bool rgb = h.color_type == 2 && h.bit_depth == 8;
  if (!grey && !rgb) return kNotHandled;
  if (h.bit_depth == 16 && request != PngRequest::kUnchanged) return kNotHandled;
  if (h.width == 0 || h.height == 0) return corrupt("corrupt PNG: zero width or height");

  const int bpp = (rgb ? 3 : 1) * h.bit_depth / 8;
  const size_t row_bytes = size_t{h.width} * bpp;
  const size_t raw_size = (row_bytes + 1) * h.height;
  thread_local std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater(
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
  if (!inflater) return kNotHandled;
  std::unique_ptr<uint8_t[]> raw(new uint8_t[raw_size]);
  // Exactly raw_size bytes or it is not this image (libdeflate also checks the Adler-32).
  if (libdeflate_zlib_decompress(inflater.get(), stream.data(), stream.size(), raw.get(), raw_size, nullptr) !=
      LIBDEFLATE_SUCCESS) {
    return corrupt("corrupt PNG: damaged image data");
  }

  int type = CV_8UC1;
  if (h.bit_depth == 16) {
    type = CV_16UC1;
  } else if (request == PngRequest::kBgr || (rgb && request == PngRequest::kUnchanged)) {
    type = CV_8UC3;
  }
  cv::Mat image(static_cast<int>(h.height), static_cast<int>(h.width), type);
  const std::vector<uint8_t> zeros(row_bytes, 0);
  const uint8_t* above = zeros.data();
  for (uint32_t y = 0; y < h.height; ++y) {
    uint8_t* row = raw.get() + y * (row_bytes + 1);
    if (!UnfilterRow(bpp, row[0], row + 1, above, row_bytes))
      return corrupt(fmt::format("corrupt PNG: unknown filter type {} in row {}", row[0], y));
    if (rgb) {
      RgbRowTo(request, row + 1, image.ptr<uint8_t>(static_cast<int>(y)), h.width);
    } else {
      GreyRowTo(request, h, row + 1, image.ptr<uint8_t>(static_cast<int>(y)));
    }
    above = row + 1;
  }
  *out = std::move(image);
  return DecodeStatus::kDecoded;
}

void ColorRowToGreyAsPng(const uint8_t* pixels, int channels, bool blue_first, uint8_t* out, int width) {
  const int r_at = blue_first ? 2 : 0, b_at = blue_first ? 0 : 2;
  for (int x = 0; x < width; ++x, pixels += channels) {
    const uint32_t r = pixels[r_at], g = pixels[1], b = pixels[b_at];
    out[x] =
        r == g && r == b ? static_cast<uint8_t>(r) : static_cast<uint8_t>((kRed * r + kGreen * g + kBlue * b) >> 15);
  }
}

}  // namespace f2c
