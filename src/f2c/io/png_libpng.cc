// Every other PNG (palette, interlaced, alpha, 16-bit colour, 1-4 bit grey, transparency or
// colour-management chunks) through libpng with the transformations OpenCV 4.6's PNG decoder
// asks of it, so the pixels are OpenCV's; but libpng's messages come back to us instead of
// going to stderr ("libpng error: ..." before our own line), and a damaged file is kCorrupt
// with libpng's reason.

#include <fmt/format.h>
#include <png.h>

#include <csetjmp>
#include <cstring>
#include <memory>
#include <vector>

#include "f2c/io/png.h"

namespace f2c {
namespace {

// What the handlers and the read callback share; allocated before setjmp so that a longjmp
// back to it destroys nothing half-built.
struct LibpngRead {
  const uint8_t* data = nullptr;
  size_t size = 0;
  size_t pos = 0;
  std::string error;
  cv::Mat image;
  std::vector<png_bytep> rows;
};

[[noreturn]] void OnError(png_structp png, png_const_charp message) {
  static_cast<LibpngRead*>(png_get_error_ptr(png))->error = message;
  png_longjmp(png, 1);
}

void OnWarning(png_structp, png_const_charp) {}  // as OpenCV's result: libpng carries on

void ReadBytes(png_structp png, png_bytep out, size_t n) {
  auto* read = static_cast<LibpngRead*>(png_get_io_ptr(png));
  if (n > read->size - read->pos) png_error(png, "cut short");
  std::memcpy(out, read->data + read->pos, n);
  read->pos += n;
}

// The part between setjmp and the end of the read: no automatic object with a destructor
// lives in this frame.
bool ReadWithLibpng(png_structp png, png_infop info, PngRequest request, LibpngRead* read) {
  if (setjmp(png_jmpbuf(png)) != 0) return false;
  png_set_read_fn(png, read, ReadBytes);
  png_read_info(png, info);
  png_uint_32 width = 0, height = 0;
  int bit_depth = 0, color_type = 0;
  png_get_IHDR(png, info, &width, &height, &bit_depth, &color_type, nullptr, nullptr, nullptr);
  if (uint64_t{width} * height > (uint64_t{1} << 25)) {
    read->error = fmt::format("PNG of {} x {} pixels: over the 32-megapixel limit for RGB-D frames", width, height);
    return false;
  }
  // The Mat OpenCV's imdecode makes for these flags: 16 bits only when unchanged; 3 channels
  // for a source of several (grey and alpha too) unless grey was asked, alpha dropped.
  const bool colour_source = (color_type & PNG_COLOR_MASK_COLOR) != 0;
  const bool several = colour_source || color_type == PNG_COLOR_TYPE_GRAY_ALPHA;
  const int channels = request == PngRequest::kBgr || (request == PngRequest::kUnchanged && several) ? 3 : 1;
  const bool sixteen = bit_depth == 16 && request == PngRequest::kUnchanged;
  read->image.create(static_cast<int>(height), static_cast<int>(width),
                     CV_MAKETYPE(sixteen ? CV_16U : CV_8U, channels));
  // OpenCV's PngDecoder::readData, call for call.
  if (!sixteen && bit_depth == 16) {
    png_set_strip_16(png);
  } else if (sixteen) {
    png_set_swap(png);  // little-endian machines
  }
  png_set_strip_alpha(png);
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (!colour_source && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (colour_source && channels == 3) {
    png_set_bgr(png);
  } else if (channels == 3) {
    png_set_gray_to_rgb(png);
  } else {
    png_set_rgb_to_gray(png, 1, 0.299, 0.587);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  read->rows.resize(height);
  for (png_uint_32 y = 0; y < height; ++y) read->rows[y] = read->image.ptr<png_byte>(static_cast<int>(y));
  png_read_image(png, read->rows.data());
  png_read_end(png, nullptr);
  return true;
}

}  // namespace

DecodeStatus DecodePngWithLibpng(std::string_view bytes, PngRequest request, cv::Mat* out, std::string* problem) {
  static constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) return DecodeStatus::kNotHandled;
  auto read = std::make_unique<LibpngRead>();
  read->data = reinterpret_cast<const uint8_t*>(bytes.data());
  read->size = bytes.size();
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, read.get(), OnError, OnWarning);
  if (png == nullptr) return DecodeStatus::kNotHandled;
  png_infop info = png_create_info_struct(png);
  const bool ok = info != nullptr && ReadWithLibpng(png, info, request, read.get());
  png_destroy_read_struct(&png, info != nullptr ? &info : nullptr, nullptr);
  if (!ok) {
    if (problem) {
      *problem = read->error.rfind("PNG of ", 0) == 0 ? read->error : "corrupt PNG: " + read->error;
    }
    return DecodeStatus::kCorrupt;
  }
  *out = std::move(read->image);
  return DecodeStatus::kDecoded;
}

}  // namespace f2c
