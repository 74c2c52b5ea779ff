#include "f2c/io/image_write.h"

#include <libdeflate.h>
#include <turbojpeg.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

void PutBigEndian32(std::string* out, uint32_t v) {
  const char bytes[4] = {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
                         static_cast<char>(v)};
  out->append(bytes, 4);
}

// A chunk: length, type, data, and the CRC-32 of type and data.
void PutChunk(std::string* out, const char (&type)[5], const std::string& data) {
  PutBigEndian32(out, static_cast<uint32_t>(data.size()));
  const size_t start = out->size();
  out->append(type, 4);
  out->append(data);
  PutBigEndian32(out, libdeflate_crc32(0, out->data() + start, out->size() - start));
}

int Paeth(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

// Appends `row` filtered by the filter (None, Sub, Up, Average, Paeth) whose bytes, read as
// signed, have the least absolute sum.
void PutFilteredRow(const uint8_t* row, const uint8_t* above, size_t n, int bpp, std::string* out) {
  thread_local std::array<std::vector<uint8_t>, 5> candidates;
  size_t best = 0;
  long best_sum = -1;
  for (int f = 0; f < 5; ++f) {
    std::vector<uint8_t>& c = candidates[f];
    c.resize(n);
    long sum = 0;
    for (size_t i = 0; i < n; ++i) {
      const int left = i >= static_cast<size_t>(bpp) ? row[i - bpp] : 0;
      const int up = above ? above[i] : 0;
      const int upper_left = above && i >= static_cast<size_t>(bpp) ? above[i - bpp] : 0;
      const int predicted = f == 0   ? 0
                            : f == 1 ? left
                            : f == 2 ? up
                            : f == 3 ? (left + up) / 2
                                     : Paeth(left, up, upper_left);
      c[i] = static_cast<uint8_t>(row[i] - predicted);
      sum += std::abs(static_cast<int8_t>(c[i]));
    }
    if (best_sum < 0 || sum < best_sum) best = f, best_sum = sum;
  }
  out->push_back(static_cast<char>(best));
  out->append(reinterpret_cast<const char*>(candidates[best].data()), n);
}

}  // namespace

std::string EncodePng(const cv::Mat& image) {
  int colour_type = 0, bit_depth = 8;
  switch (image.type()) {
    case CV_8UC1:
      colour_type = 0;
      break;
    case CV_8UC3:
      colour_type = 2;
      break;
    case CV_8UC4:
      colour_type = 6;
      break;
    case CV_16UC1:
      colour_type = 0, bit_depth = 16;
      break;
    default:
      ThrowInputError("PNG", "only 8-bit grey, BGR or BGRA and 16-bit grey images are written");
  }
  const int channels = image.channels(), bpp = channels * bit_depth / 8;
  const size_t row_bytes = static_cast<size_t>(image.cols) * bpp;
  // Rows in PNG's byte order (RGB, big-endian 16-bit), each filtered.
  std::string raw;
  raw.reserve((row_bytes + 1) * image.rows);
  std::vector<uint8_t> previous, row(row_bytes);
  for (int y = 0; y < image.rows; ++y) {
    const uint8_t* in = image.ptr<uint8_t>(y);
    if (bit_depth == 16) {
      for (int x = 0; x < image.cols; ++x) {
        const uint16_t v = image.ptr<uint16_t>(y)[x];
        row[2 * x] = static_cast<uint8_t>(v >> 8), row[2 * x + 1] = static_cast<uint8_t>(v);
      }
    } else if (channels >= 3) {
      for (int x = 0; x < image.cols; ++x) {
        const uint8_t* p = in + x * channels;
        uint8_t* q = row.data() + x * channels;
        q[0] = p[2], q[1] = p[1], q[2] = p[0];  // BGR(A) -> RGB(A)
        if (channels == 4) q[3] = p[3];
      }
    } else {
      std::memcpy(row.data(), in, row_bytes);
    }
    PutFilteredRow(row.data(), previous.empty() ? nullptr : previous.data(), row_bytes, bpp, &raw);
    previous = row;
  }
  std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)> deflater(libdeflate_alloc_compressor(6),
                                                                                    libdeflate_free_compressor);
  std::string compressed(libdeflate_zlib_compress_bound(deflater.get(), raw.size()), '\0');
  compressed.resize(
      libdeflate_zlib_compress(deflater.get(), raw.data(), raw.size(), compressed.data(), compressed.size()));

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string header;
  PutBigEndian32(&header, static_cast<uint32_t>(image.cols));
  PutBigEndian32(&header, static_cast<uint32_t>(image.rows));
  header += {static_cast<char>(bit_depth), static_cast<char>(colour_type), 0, 0, 0};
  PutChunk(&png, "IHDR", header);
  PutChunk(&png, "IDAT", compressed);
  PutChunk(&png, "IEND", "");
  return png;
}

std::string EncodeJpeg(const cv::Mat& image, int quality) {
  if (image.type() != CV_8UC3 && image.type() != CV_8UC1) {
    ThrowInputError("JPEG", "only 8-bit BGR or grey images are written");
  }
  std::unique_ptr<void, int (*)(tjhandle)> handle(tjInitCompress(), tjDestroy);
  const bool grey = image.channels() == 1;
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  const int failed = tjCompress2(handle.get(), image.data, image.cols, static_cast<int>(image.step[0]), image.rows,
                                 grey ? TJPF_GRAY : TJPF_BGR, &buffer, &size, grey ? TJSAMP_GRAY : TJSAMP_420, quality,
                                 TJFLAG_ACCURATEDCT);
  std::string jpeg = failed ? std::string() : std::string(reinterpret_cast<const char*>(buffer), size);
  tjFree(buffer);
  if (failed) ThrowInputError("JPEG", std::string("cannot encode: ") + tjGetErrorStr2(handle.get()));
  return jpeg;
}

void WritePngFile(const std::filesystem::path& path, const cv::Mat& image) { WriteFileAtomic(path, EncodePng(image)); }

}  // namespace f2c
