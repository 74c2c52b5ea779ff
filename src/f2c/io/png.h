#pragma once
// A fast path for the PNGs RGB-D recordings are made of: 16-bit grey depth and 8-bit RGB or
// grey colour, non-interlaced. The zlib stream is inflated by libdeflate (whole-buffer, about
// twice zlib's speed) and the rows are unfiltered and converted in one pass; decoding was a
// third of the odometry's work on PNG sequences (docs/odometry.md). The result equals
// OpenCV's imdecode with the matching flag bit for bit, grey conversion included (libpng's
// fixed-point weights), so the caller can fall back to libpng for everything else.

#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "f2c/io/decode_status.h"

namespace f2c {

// What the caller wants, as OpenCV's imread flags:
//   kGray:      cv::IMREAD_GRAYSCALE (8-bit grey; RGB converted)
//   kBgr:       cv::IMREAD_COLOR (8-bit BGR; grey replicated)
//   kUnchanged: cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR (16-bit grey stays 16-bit)
enum class PngRequest { kGray, kBgr, kUnchanged };

// Decodes `bytes` into *out. kNotHandled, with *out untouched, for PNGs this path leaves to
// DecodePngWithLibpng (palette, alpha, interlaced, 16-bit colour, 1-4 bit grey, a transparency or
// colour-management chunk, a damaged ancillary chunk, or not a PNG).
// kCorrupt for a damaged one: cut short, a bad checksum in IHDR, IDAT or IEND, a broken
// zlib stream, image data of the wrong size, an unknown row filter; and over 32 megapixels
// (no RGB-D camera's frame is that large: refused before allocating).
DecodeStatus DecodePng(std::string_view bytes, PngRequest request, cv::Mat* out, std::string* problem = nullptr);

// Any PNG, through libpng with the transformations OpenCV's decoder asks of it (the same
// pixels as its imdecode with the matching flag), for the kinds DecodePng leaves: libpng's
// messages become `problem` instead of lines on stderr. kCorrupt for a damaged file (cut
// short, an unknown critical chunk, an impossible header, ...) or one over 32 megapixels;
// kNotHandled only for bytes that are not a PNG.
DecodeStatus DecodePngWithLibpng(std::string_view bytes, PngRequest request, cv::Mat* out,
                                 std::string* problem = nullptr);

// Colour pixels (3 or 4 channels, R first or B first) to grey as a PNG of the same pixels
// decodes to grey (libpng's weights and rounding, above): raw colour in a recording and the
// same colour in a PNG file give the same grey image.
void ColorRowToGreyAsPng(const uint8_t* pixels, int channels, bool blue_first, uint8_t* out, int width);

}  // namespace f2c
