#include "f2c/io/png.h"

#include <gtest/gtest.h>
#include <libdeflate.h>
#include <png.h>

#include <opencv2/imgcodecs.hpp>
#include <random>
#include <string>
#include <vector>

namespace f2c {
namespace {

// A test image: smooth ramps (which the predictive filters turn into small numbers) with
// noise, and flat grey patches (R = G = B, which the grey conversion passes through).
cv::Mat PngTestImage(int type, uint32_t seed) {
  cv::Mat image(37, 53, type);
  std::mt19937 rng(seed);
  const int channels = image.channels();
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const bool patch = x < 10 && y < 10;
      const int base = static_cast<int>(rng() % 256);
      for (int c = 0; c < channels; ++c) {
        const int v = patch ? base : (x * 7 + y * 3 + c * 40 + static_cast<int>(rng() % 9)) % 256;
        if (image.depth() == CV_16U) {
          image.ptr<uint16_t>(y)[x * channels + c] = static_cast<uint16_t>(v * 257 + static_cast<int>(rng() % 200));
        } else {
          image.ptr<uint8_t>(y)[x * channels + c] = static_cast<uint8_t>(v);
        }
      }
    }
  }
  return image;
}

void Put32(std::string* s, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) s->push_back(static_cast<char>((v >> shift) & 0xff));
}

void PutChunk(std::string* png, const std::string& type, const std::string& body) {
  Put32(png, static_cast<uint32_t>(body.size()));
  const std::string typed = type + body;
  png->append(typed);
  Put32(png, libdeflate_crc32(0, typed.data(), typed.size()));
}

// A PNG encoded independently of libpng: `filter` (0-4; 5 writes an invalid filter type) on
// every row, or row % 5 for -1, so
// each of the five filters is checked against OpenCV's decoder (libpng). `image` is grey or
// RGB (as OpenCV's BGR), 8 or 16 bits. The zlib stream is split over two IDAT chunks.
std::string HandMadePng(const cv::Mat& image, int filter, const std::string& extra_chunk = {}) {
  const int channels = image.channels(), bytes = image.depth() == CV_16U ? 2 : 1, bpp = channels * bytes;
  const size_t row_bytes = static_cast<size_t>(image.cols) * bpp;
  std::vector<uint8_t> rows(image.rows * row_bytes);
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      for (int c = 0; c < channels; ++c) {
        const int source = channels == 3 ? 2 - c : c;  // BGR to RGB
        uint8_t* out = &rows[y * row_bytes + x * bpp + c * bytes];
        if (bytes == 2) {
          const uint16_t v = image.ptr<uint16_t>(y)[x * channels + source];
          out[0] = static_cast<uint8_t>(v >> 8), out[1] = static_cast<uint8_t>(v & 0xff);
        } else {
          out[0] = image.ptr<uint8_t>(y)[x * channels + source];
        }
      }
    }
  }
  std::vector<uint8_t> filtered;
  for (int y = 0; y < image.rows; ++y) {
    const int f = filter < 0 ? y % 5 : filter;
    filtered.push_back(static_cast<uint8_t>(f));
    const uint8_t* row = &rows[y * row_bytes];
    // The row above by its own pointer: row[i - row_bytes] wraps the unsigned offset
    // (undefined behaviour, UBSan's pointer-overflow check).
    const uint8_t* above = y > 0 ? &rows[(y - 1) * row_bytes] : nullptr;
    for (size_t i = 0; i < row_bytes; ++i) {
      const int a = i >= static_cast<size_t>(bpp) ? row[i - bpp] : 0;
      const int b = above ? above[i] : 0;
      const int c = above && i >= static_cast<size_t>(bpp) ? above[i - bpp] : 0;
      const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
      const int predictor[5] = {0, a, b, (a + b) / 2, pa <= pb && pa <= pc ? a : (pb <= pc ? b : c)};
      filtered.push_back(static_cast<uint8_t>(row[i] - predictor[f > 4 ? 0 : f]));  // f > 4: invalid
    }
  }
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(6);
  std::string stream(libdeflate_zlib_compress_bound(compressor, filtered.size()), '\0');
  stream.resize(libdeflate_zlib_compress(compressor, filtered.data(), filtered.size(), stream.data(), stream.size()));
  libdeflate_free_compressor(compressor);

  std::string png("\x89PNG\r\n\x1a\n", 8), header;
  Put32(&header, image.cols);
  Put32(&header, image.rows);
  header += {static_cast<char>(8 * bytes), static_cast<char>(channels == 3 ? 2 : 0), 0, 0, 0};
  PutChunk(&png, "IHDR", header);
  PutChunk(&png, "tEXt", std::string("Comment\0test", 12));  // ancillary, no effect on pixels
  if (!extra_chunk.empty()) PutChunk(&png, extra_chunk.substr(0, 4), extra_chunk.substr(4));
  PutChunk(&png, "IDAT", stream.substr(0, stream.size() / 2));
  PutChunk(&png, "IDAT", stream.substr(stream.size() / 2));
  PutChunk(&png, "IEND", "");
  return png;
}

cv::Mat OpenCv(const std::string& png, int flags) {
  return cv::imdecode(cv::Mat(1, static_cast<int>(png.size()), CV_8U, const_cast<char*>(png.data())), flags);
}

void ExpectSame(const cv::Mat& ours, const cv::Mat& theirs) {
  ASSERT_FALSE(theirs.empty());
  ASSERT_EQ(ours.type(), theirs.type());
  ASSERT_EQ(ours.size(), theirs.size());
  EXPECT_EQ(cv::norm(ours, theirs, cv::NORM_INF), 0.0);
}

struct Case {
  PngRequest request;
  int flags;
};
const Case kCases[] = {{PngRequest::kGray, cv::IMREAD_GRAYSCALE},
                       {PngRequest::kBgr, cv::IMREAD_COLOR},
                       {PngRequest::kUnchanged, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR}};

TEST(DecodePng, RgbAndGreyEqualOpenCvForEveryFilterAndRequest) {
  for (int type : {CV_8UC3, CV_8UC1}) {
    for (int filter = -1; filter <= 4; ++filter) {
      const std::string png = HandMadePng(PngTestImage(type, 1 + filter + 10 * type), filter);
      for (const Case& c : kCases) {
        cv::Mat ours;
        ASSERT_EQ(DecodePng(png, c.request, &ours), DecodeStatus::kDecoded) << "type " << type << " filter " << filter;
        ExpectSame(ours, OpenCv(png, c.flags));
      }
    }
  }
}

TEST(DecodePng, SixteenBitDepthEqualsOpenCv) {
  for (int filter = -1; filter <= 4; ++filter) {
    const cv::Mat depth = PngTestImage(CV_16UC1, 21 + filter);
    const std::string png = HandMadePng(depth, filter);
    cv::Mat ours;
    ASSERT_EQ(DecodePng(png, PngRequest::kUnchanged, &ours), DecodeStatus::kDecoded) << "filter " << filter;
    ExpectSame(ours, depth);
    ExpectSame(ours, OpenCv(png, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR));
  }
}

TEST(DecodePng, EqualsOpenCvOnItsOwnFiles) {
  // libpng's own encoder picks a filter per row; every compression level.
  for (int level = 0; level <= 9; level += 3) {
    std::vector<uchar> buffer;
    cv::imencode(".png", PngTestImage(CV_8UC3, 40 + level), buffer, {cv::IMWRITE_PNG_COMPRESSION, level});
    const std::string png(buffer.begin(), buffer.end());
    for (const Case& c : kCases) {
      cv::Mat ours;
      ASSERT_EQ(DecodePng(png, c.request, &ours), DecodeStatus::kDecoded) << "level " << level;
      ExpectSame(ours, OpenCv(png, c.flags));
    }
  }
}

TEST(DecodePng, LeavesOtherKindsToOpenCv) {
  cv::Mat out;
  const cv::Mat rgb = PngTestImage(CV_8UC3, 5);
  // Alpha, 16-bit colour, 16-bit asked as 8-bit, a gamma chunk, a JPEG.
  std::vector<uchar> buffer;
  cv::imencode(".png", PngTestImage(CV_8UC4, 6), buffer);
  EXPECT_EQ(DecodePng(std::string(buffer.begin(), buffer.end()), PngRequest::kBgr, &out), DecodeStatus::kNotHandled);
  cv::imencode(".png", PngTestImage(CV_16UC3, 7), buffer);
  EXPECT_EQ(DecodePng(std::string(buffer.begin(), buffer.end()), PngRequest::kUnchanged, &out),
            DecodeStatus::kNotHandled);
  EXPECT_EQ(DecodePng(HandMadePng(PngTestImage(CV_16UC1, 8), 1), PngRequest::kGray, &out), DecodeStatus::kNotHandled);
  EXPECT_EQ(DecodePng(HandMadePng(rgb, 1, std::string("gAMA\0\0\xb1\x8f", 8)), PngRequest::kGray, &out),
            DecodeStatus::kNotHandled);
  EXPECT_EQ(DecodePng("\xff\xd8\xff\xe0 not a png", PngRequest::kGray, &out), DecodeStatus::kNotHandled);
  EXPECT_TRUE(out.empty());  // untouched
}

// A header that claims 100000 x 100000 pixels (20 GB of 16-bit depth) is refused from the
// header, before anything is allocated.
TEST(DecodePng, RefusesAnOversizedImageFromItsHeader) {
  std::string png = "\x89PNG\r\n\x1a\n";
  std::string ihdr;
  Put32(&ihdr, 100000), Put32(&ihdr, 100000);
  ihdr += std::string("\x10\0\0\0\0", 5);  // 16-bit grey, deflate, no interlace
  PutChunk(&png, "IHDR", ihdr);
  PutChunk(&png, "IDAT", std::string("\x78\x9c\x03\0\0\0\0\x01", 8));
  PutChunk(&png, "IEND", "");
  cv::Mat out;
  std::string what;
  EXPECT_EQ(DecodePng(png, PngRequest::kUnchanged, &out, &what), DecodeStatus::kCorrupt);
  EXPECT_EQ(what, "PNG of 100000 x 100000 pixels: over the 32-megapixel limit for RGB-D frames");
  EXPECT_TRUE(out.empty());
}

TEST(DecodePng, SaysHowADamagedFileIsDamaged) {
  const cv::Mat rgb = PngTestImage(CV_8UC3, 5);
  const std::string png = HandMadePng(rgb, 4);
  cv::Mat out;
  ASSERT_EQ(DecodePng(png, PngRequest::kGray, &out), DecodeStatus::kDecoded);
  const cv::Mat decoded = out;
  auto problem = [&](const std::string& bytes) {
    std::string what;
    EXPECT_EQ(DecodePng(bytes, PngRequest::kGray, &out, &what), DecodeStatus::kCorrupt);
    return what;
  };
  std::string flipped = png;
  flipped[png.size() - 40] ^= 0x10;  // inside the second IDAT
  EXPECT_EQ(problem(flipped), "corrupt PNG: bad checksum in the IDAT chunk");
  EXPECT_EQ(problem(png.substr(0, png.size() - 30)), "corrupt PNG: the IDAT chunk is cut short");
  EXPECT_EQ(problem(png.substr(0, png.size() - 12)), "corrupt PNG: no IEND chunk (cut short?)");
  EXPECT_EQ(problem(HandMadePng(rgb, 5)), "corrupt PNG: unknown filter type 5 in row 0");
  EXPECT_EQ(out.data, decoded.data);  // untouched by the failures
  // A damaged ancillary chunk is libpng's to skip.
  std::string text = HandMadePng(rgb, 1);
  text[text.find("Comment") + 2] ^= 1;
  EXPECT_EQ(DecodePng(text, PngRequest::kGray, &out), DecodeStatus::kNotHandled);
}

// A PNG written by libpng: `samples` holds each row's samples (palette indices, grey levels,
// or R G B [A] in the file's order), `bit_depth` bits each, packed as the format packs them.
struct LibpngKind {
  const char* name;
  int bit_depth, color_type, interlace;
  bool transparency;
};

std::string WriteWithLibpng(const LibpngKind& kind, int width, int height, uint32_t seed) {
  const int channels = kind.color_type == PNG_COLOR_TYPE_RGB          ? 3
                       : kind.color_type == PNG_COLOR_TYPE_RGB_ALPHA  ? 4
                       : kind.color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                                                                      : 1;
  const int max = (1 << kind.bit_depth) - 1;
  std::mt19937 rng(seed);
  const size_t row_bytes = (static_cast<size_t>(width) * channels * kind.bit_depth + 7) / 8;
  std::vector<std::vector<png_byte>> rows(height, std::vector<png_byte>(row_bytes, 0));
  for (int y = 0; y < height; ++y) {
    for (int i = 0; i < width * channels; ++i) {
      const int v = ((i * 7 + y * 3) * max / (width * channels + height * 2) + static_cast<int>(rng() % 3)) % (max + 1);
      if (kind.bit_depth == 16) {
        rows[y][2 * i] = static_cast<png_byte>(v >> 8), rows[y][2 * i + 1] = static_cast<png_byte>(v & 255);
      } else {
        const int bit = i * kind.bit_depth;
        rows[y][bit / 8] |= static_cast<png_byte>(v << (8 - kind.bit_depth - bit % 8));
      }
    }
  }
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, size_t n) {
        static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<char*>(data), n);
      },
      nullptr);
  png_set_IHDR(png, info, width, height, kind.bit_depth, kind.color_type, kind.interlace, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  std::vector<png_color> palette(max + 1);
  std::vector<png_byte> alpha(max + 1);
  if (kind.color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i <= max; ++i) {
      palette[i] = {static_cast<png_byte>(rng()), static_cast<png_byte>(rng()), static_cast<png_byte>(rng())};
      alpha[i] = static_cast<png_byte>(rng());
    }
    png_set_PLTE(png, info, palette.data(), max + 1);
    if (kind.transparency) png_set_tRNS(png, info, alpha.data(), max + 1, nullptr);
  } else if (kind.transparency) {
    png_color_16 key{};
    key.gray = key.red = key.green = key.blue = static_cast<png_uint_16>(max / 2);
    png_set_tRNS(png, info, nullptr, 0, &key);
  }
  std::vector<png_bytep> pointers;
  for (auto& row : rows) pointers.push_back(row.data());
  png_set_rows(png, info, pointers.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

const LibpngKind kLibpngKinds[] = {
    {"palette 8-bit", 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, false},
    {"palette 4-bit, transparency", 4, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE, true},
    {"palette 2-bit, interlaced", 2, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_ADAM7, false},
    {"RGB 8-bit, interlaced", 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_ADAM7, false},
    {"RGB 16-bit", 16, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, false},
    {"RGB 8-bit, transparent colour", 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, true},
    {"RGBA 16-bit, interlaced", 16, PNG_COLOR_TYPE_RGB_ALPHA, PNG_INTERLACE_ADAM7, false},
    {"grey 1-bit", 1, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, false},
    {"grey 2-bit, interlaced", 2, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_ADAM7, false},
    {"grey 4-bit, transparent level", 4, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, true},
    {"grey 16-bit, interlaced", 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_ADAM7, false},
    {"grey and alpha 8-bit", 8, PNG_COLOR_TYPE_GRAY_ALPHA, PNG_INTERLACE_NONE, false},
};

// The kinds the fast path leaves: the same pixels as OpenCV's imdecode for every request.
TEST(DecodePngWithLibpng, EqualsOpenCvForEveryKindAndRequest) {
  for (const LibpngKind& kind : kLibpngKinds) {
    const std::string png = WriteWithLibpng(kind, 45, 31, kind.bit_depth * 10 + kind.color_type);
    for (const Case& c : kCases) {
      SCOPED_TRACE(std::string(kind.name) + ", flags " + std::to_string(c.flags));
      cv::Mat ours;
      std::string problem;
      ASSERT_EQ(DecodePngWithLibpng(png, c.request, &ours, &problem), DecodeStatus::kDecoded) << problem;
      ExpectSame(ours, OpenCv(png, c.flags));
    }
  }
}

// Damage is kCorrupt with libpng's reason (which libpng would otherwise print to stderr).
TEST(DecodePngWithLibpng, SaysHowADamagedFileIsDamaged) {
  const std::string palette = WriteWithLibpng(kLibpngKinds[0], 45, 31, 1);
  const std::string interlaced = WriteWithLibpng(kLibpngKinds[3], 45, 31, 2);
  auto problem = [](const std::string& bytes) {
    cv::Mat out;
    std::string what;
    EXPECT_EQ(DecodePngWithLibpng(bytes, PngRequest::kBgr, &out, &what), DecodeStatus::kCorrupt);
    EXPECT_TRUE(out.empty());
    return what;
  };
  EXPECT_EQ(problem(palette.substr(0, palette.size() * 2 / 3)), "corrupt PNG: cut short");
  EXPECT_EQ(problem(interlaced.substr(0, interlaced.size() / 2)), "corrupt PNG: cut short");
  std::string sixteen_bit_palette = palette;
  sixteen_bit_palette[24] = 16;  // IHDR's bit depth, its checksum made right again
  const size_t ihdr = 8;
  const uint32_t crc = libdeflate_crc32(0, sixteen_bit_palette.data() + ihdr + 4, 17);
  for (int i = 0; i < 4; ++i) sixteen_bit_palette[ihdr + 21 + i] = static_cast<char>(crc >> (24 - 8 * i));
  EXPECT_EQ(problem(sixteen_bit_palette), "corrupt PNG: Invalid IHDR data");
  std::string critical = palette.substr(0, 33);
  PutChunk(&critical, "ABCD", "xyz");
  critical += palette.substr(33);
  EXPECT_EQ(problem(critical), "corrupt PNG: ABCD: unhandled critical chunk");
  cv::Mat out;
  EXPECT_EQ(DecodePngWithLibpng("\xff\xd8\xff\xe0 not a png", PngRequest::kGray, &out), DecodeStatus::kNotHandled);
}

}  // namespace
}  // namespace f2c
