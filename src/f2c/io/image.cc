#include "f2c/io/image.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <string_view>
#include <tuple>
#include <filesystem>
#include <cstdlib>
#include <string>
#include <vector>
#include <cstring>
#include <fstream>
#include <memory>
#include <dlfcn.h>
#include <libdeflate.h>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "f2c/io/block.h"
#include "f2c/io/jpeg.h"
#include "f2c/io/png.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

PngRequest AsPngRequest(int flags) {
  if (flags == cv::IMREAD_GRAYSCALE) return PngRequest::kGray;
  if (flags == cv::IMREAD_COLOR) return PngRequest::kBgr;
  return PngRequest::kUnchanged;  // cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR
}

// PNG, JPEG, PNM (P1-P6), TIFF or BMP, by their first bytes. OpenCV picks its decoder by its
// own signature checks, in its own order; every other format's signature sits at the start of
// the file (so it cannot also match one of these) except DICOM's, "DICM" at byte 128, which
// OpenCV tries first: such files are refused too.
bool LooksLikeRgbdImage(std::string_view b) {
  if (b.size() >= 132 && b.substr(128, 4) == "DICM") return false;
  auto starts = [&](std::string_view prefix) { return b.substr(0, prefix.size()) == prefix; };
  return starts("\x89PNG") || starts("\xff\xd8") || (b.size() >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') ||
         starts(std::string_view("II*\0", 4)) || starts(std::string_view("MM\0*", 4)) || starts("BM");
}

// OpenCV's decoders (opencv_codecs.cc), loaded at their first use: from the build folder, or
// from beside the running program. Null when neither is there.
using OpenCvDecode = int (*)(const unsigned char*, size_t, int, cv::Mat*, char*, size_t);
OpenCvDecode OpenCvDecoder() {
  static const OpenCvDecode decode = []() -> OpenCvDecode {
    std::vector<std::string> candidates = {F2C_OPENCV_CODECS_PATH};
    char exe[4096];
    const ssize_t n = ::readlink("/proc/self/exe", exe, sizeof(exe) - 1);
    if (n > 0) {
      candidates.push_back(
          (std::filesystem::path(std::string(exe, n)).parent_path() / F2C_OPENCV_CODECS_NAME).string());
    }
    candidates.push_back(F2C_OPENCV_CODECS_NAME);  // the loader's own search path
    // OpenCV allocates what a header claims, up to a gigapixel by default: a damaged PNM or
    // BMP header of 20 bytes made it allocate 2.7 GB (found by fuzz_images). Its limit is
    // read when imgcodecs loads, so it is set before (unless the user set it), to the
    // 32-megapixel limit of our own PNG and JPEG decoders.
    ::setenv("OPENCV_IO_MAX_IMAGE_PIXELS", "33554432", /*overwrite=*/0);
    for (const std::string& candidate : candidates) {
      if (void* library = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL)) {
        return reinterpret_cast<OpenCvDecode>(::dlsym(library, "f2c_opencv_imdecode"));
      }
    }
    return nullptr;
  }();
  return decode;
}

}  // namespace

cv::Mat DecodeImageFile(const std::filesystem::path& path, int flags) {
  if (!std::filesystem::is_regular_file(path)) ThrowInputError(path, "missing frame image");
  return DecodeImageBytes(ReadFileToString(path), path.string(), flags);
}

cv::Mat DecodeImageBytes(const std::string& bytes, const std::string& path, int flags) {
  cv::Mat image;
  std::string problem;
  DecodeStatus status = DecodePng(bytes, AsPngRequest(flags), &image, &problem);
  if (status == DecodeStatus::kNotHandled) status = DecodePngWithLibpng(bytes, AsPngRequest(flags), &image, &problem);
  if (status == DecodeStatus::kNotHandled && (flags == cv::IMREAD_COLOR || flags == cv::IMREAD_GRAYSCALE)) {
    status = DecodeJpeg(bytes, flags == cv::IMREAD_GRAYSCALE, &image, &problem);
  }
  if (status == DecodeStatus::kDecoded) return image;
  if (status == DecodeStatus::kCorrupt) ThrowInputError(path, problem);
  // OpenCV only for the kinds RGB-D recordings come in: its other decoders (DICOM, JPEG 2000,
  // OpenEXR, ...) are never needed here, and a damaged file can abort inside them (found by
  // fuzz_images: gdcm's assertion on bytes that looked like DICOM).
  if (!LooksLikeRgbdImage(bytes)) ThrowInputError(path, "cannot decode image (corrupt or not an image)");
  const OpenCvDecode decode = OpenCvDecoder();
  if (decode == nullptr) {
    ThrowInputError(path, std::string("this kind of image needs OpenCV's decoders, and ") + F2C_OPENCV_CODECS_NAME +
                              " was found neither in the build folder nor beside the program");
  }
  char reason[256] = {};
  if (!decode(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), flags, &image, reason,
              sizeof(reason))) {
    if (std::string_view(reason).find("CV_IO_MAX_IMAGE_PIXELS") != std::string_view::npos) {
      ThrowInputError(path, "corrupt image: its header claims over the 32-megapixel limit for RGB-D frames");
    }
    ThrowInputError(path, reason[0] != '\0' ? std::string("corrupt image: ") + reason
                                            : std::string("cannot decode image (corrupt or not an image)"));
  }
  return image;
}

std::string ReadFileRange(const std::filesystem::path& path, uint64_t offset, uint64_t size) {
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowInputError(path, "cannot open the recording");
  std::string bytes(size, '\0');
  in.seekg(static_cast<std::streamoff>(offset));
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size))) {
    ThrowInputError(path, fmt::format("cut short: {} bytes at {} lie past its end", size, offset));
  }
  return bytes;
}

std::string ReadEmbeddedBytes(const std::filesystem::path& path, const EmbeddedImage& e) {
  if (e.sqlite_row >= 0) return ReadSqliteBlob(path, e.sqlite_row, e.offset, e.size);
  if (!e.block) return ReadFileRange(path, e.offset, e.size);
  const std::shared_ptr<const std::string> block = ReadBlock(path, *e.block);
  if (e.offset > block->size() || e.size > block->size() - e.offset) {
    ThrowInputError(path, fmt::format("{} bytes at {} of a {} chunk lie past its end ({} bytes)", e.size, e.offset,
                                      CompressionName(e.block->compression), block->size()));
  }
  return block->substr(e.offset, e.size);
}

namespace {

// The rows of a raw image: `bytes` holds `height` rows of `step` bytes (packed when step is
// 0), each starting with `width` pixels of `pixel_bytes`.
cv::Mat RawImage(const std::string& bytes, const EmbeddedImage& e, int type, const std::string& where) {
  const uint64_t pixel_bytes = CV_ELEM_SIZE(type);
  const uint64_t row = static_cast<uint64_t>(e.width) * pixel_bytes;
  const uint64_t step = e.step == 0 ? row : e.step;
  if (e.width <= 0 || e.height <= 0 || step < row || bytes.size() != step * static_cast<uint64_t>(e.height)) {
    ThrowInputError(where, fmt::format("raw image of {} bytes for {}x{} pixels of {} bytes in rows of {}", bytes.size(),
                                       e.width, e.height, pixel_bytes, step));
  }
  return cv::Mat(e.height, e.width, type, const_cast<char*>(bytes.data()), step);
}

cv::Mat ConvertColor(const cv::Mat& raw, int flags, int to_bgr, int to_gray) {
  if (flags != cv::IMREAD_COLOR && flags != cv::IMREAD_GRAYSCALE) return raw.clone();
  cv::Mat out;
  // Grey from RGB(A) or BGR(A) as from a PNG of the same pixels (io/png.h).
  if (flags == cv::IMREAD_GRAYSCALE && (raw.channels() == 3 || raw.channels() == 4) && raw.depth() == CV_8U) {
    const bool blue_first = to_bgr == -1 || to_bgr == cv::COLOR_BGRA2BGR;
    out.create(raw.rows, raw.cols, CV_8UC1);
    for (int y = 0; y < raw.rows; ++y) {
      ColorRowToGreyAsPng(raw.ptr<uint8_t>(y), raw.channels(), blue_first, out.ptr<uint8_t>(y), raw.cols);
    }
    return out;
  }
  const int code = flags == cv::IMREAD_GRAYSCALE ? to_gray : to_bgr;
  if (code < 0) {
    out = raw.clone();
  } else {
    cv::cvtColor(raw, out, code);
  }
  return out;
}

}  // namespace

// A frame's image: its own file, or the part of a recording it is embedded in.
cv::Mat ReadFrameImage(const std::filesystem::path& path, const std::optional<EmbeddedImage>& embedded, int flags) {
  if (!embedded) return DecodeImageFile(path, flags);
  const EmbeddedImage& e = *embedded;
  const std::string where = e.block
                                ? fmt::format("{} ({} bytes at {} of the {} chunk at byte {})", path.string(), e.size,
                                              e.offset, CompressionName(e.block->compression), e.block->offset)
                                : fmt::format("{} (bytes {}-{})", path.string(), e.offset, e.offset + e.size);
  const std::string bytes = ReadEmbeddedBytes(path, e);
  using F = EmbeddedImage::Format;
  switch (e.format) {
    case F::kEncoded:
      return DecodeImageBytes(bytes, where, flags);
    case F::kRgb8:
      return ConvertColor(RawImage(bytes, e, CV_8UC3, where), flags, cv::COLOR_RGB2BGR, cv::COLOR_RGB2GRAY);
    case F::kBgr8:
      return ConvertColor(RawImage(bytes, e, CV_8UC3, where), flags, -1, cv::COLOR_BGR2GRAY);
    case F::kRgba8:
      return ConvertColor(RawImage(bytes, e, CV_8UC4, where), flags, cv::COLOR_RGBA2BGR, cv::COLOR_RGBA2GRAY);
    case F::kBgra8:
      return ConvertColor(RawImage(bytes, e, CV_8UC4, where), flags, cv::COLOR_BGRA2BGR, cv::COLOR_BGRA2GRAY);
    case F::kMono8:
      return ConvertColor(RawImage(bytes, e, CV_8UC1, where), flags, cv::COLOR_GRAY2BGR, -1);
    case F::kYuyv:
    case F::kUyvy: {
      if (e.width % 2 != 0) ThrowInputError(where, fmt::format("YUV 4:2:2 image of odd width {}", e.width));
      const bool yuyv = e.format == F::kYuyv;
      return ConvertColor(RawImage(bytes, e, CV_8UC2, where), flags,
                          yuyv ? cv::COLOR_YUV2BGR_YUYV : cv::COLOR_YUV2BGR_UYVY,
                          yuyv ? cv::COLOR_YUV2GRAY_YUYV : cv::COLOR_YUV2GRAY_UYVY);
    }
    case F::kRawU16: {
      cv::Mat depth = RawImage(bytes, e, CV_16UC1, where).clone();  // little-endian, as this machine
      if (e.big_endian) {
        for (int y = 0; y < depth.rows; ++y) {
          uint16_t* row = depth.ptr<uint16_t>(y);
          for (int x = 0; x < depth.cols; ++x) row[x] = static_cast<uint16_t>((row[x] >> 8) | (row[x] << 8));
        }
      }
      return depth;
    }
    case F::kFloat32: {
      // Metres to the sequence's uint16 unit, rounded; no depth (NaN, 0, negative) and depth
      // beyond the unit's range are 0, invalid.
      if (!(e.float_unit > 0)) ThrowInputError(where, "float depth without its unit");
      const cv::Mat metres = RawImage(bytes, e, CV_32FC1, where);
      cv::Mat depth(e.height, e.width, CV_16UC1);
      for (int y = 0; y < depth.rows; ++y) {
        const char* in = reinterpret_cast<const char*>(metres.ptr(y));
        uint16_t* out = depth.ptr<uint16_t>(y);
        for (int x = 0; x < depth.cols; ++x) {
          uint32_t word;
          std::memcpy(&word, in + 4 * x, 4);
          if (e.big_endian) word = __builtin_bswap32(word);
          float f;
          std::memcpy(&f, &word, 4);
          const double units = std::round(static_cast<double>(f) / e.float_unit);
          out[x] = std::isfinite(f) && units > 0 && units <= 65535 ? static_cast<uint16_t>(units) : 0;
        }
      }
      return depth;
    }
    case F::kInverseDepthPng: {
      // Metres = A / (q - B), then the sequence's uint16 unit, rounded; q = 0 is no depth, and
      // so is depth that is not positive or beyond the unit's range.
      if (!(e.float_unit > 0)) ThrowInputError(where, "inverse depth without its unit");
      const cv::Mat q = DecodeImageBytes(bytes, where, cv::IMREAD_UNCHANGED);
      if (q.type() != CV_16UC1) ThrowInputError(where, "compressedDepth image is not a 16-bit grey PNG");
      cv::Mat depth(q.size(), CV_16UC1);
      for (int y = 0; y < q.rows; ++y) {
        const uint16_t* in = q.ptr<uint16_t>(y);
        uint16_t* out = depth.ptr<uint16_t>(y);
        for (int x = 0; x < q.cols; ++x) {
          const double metres = in[x] == 0 ? 0.0 : e.quant_a / (static_cast<double>(in[x]) - e.quant_b);
          const double units = std::round(metres / e.float_unit);
          out[x] = std::isfinite(units) && units > 0 && units <= 65535 ? static_cast<uint16_t>(units) : 0;
        }
      }
      return depth;
    }
    case F::kZlibU16: {
      cv::Mat depth(e.height, e.width, CV_16UC1);
      const size_t want = static_cast<size_t>(e.width) * static_cast<size_t>(e.height) * 2;
      thread_local std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater(
          libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
      size_t got = 0;
      if (libdeflate_zlib_decompress(inflater.get(), bytes.data(), bytes.size(), depth.data, want, &got) !=
              LIBDEFLATE_SUCCESS ||
          got != want) {
        ThrowInputError(where,
                        fmt::format("damaged zlib depth (not {} bytes of {}x{} depth)", want, e.width, e.height));
      }
      return depth;
    }
  }
  ThrowInputError(where, "unknown embedded image format");
}

namespace {

// Colour from another camera resampled into the depth camera: each depth pixel's colour is
// where its point (from its depth; at infinity where it has none) projects in the colour
// image, bilinear, the colour image's edge repeated beyond it.
cv::Mat ColorIntoDepthCamera(const RgbdSequence& sequence, const RgbdFrame& frame, const cv::Mat& color) {
  const ColorCamera& camera = *sequence.color_camera;
  const CameraIntrinsics& kd = *sequence.intrinsics;
  const CameraIntrinsics& kc = camera.intrinsics;
  const Eigen::Matrix3d r = camera.color_from_depth.linear();
  const Eigen::Vector3d t = camera.color_from_depth.translation();
  // A translation makes the mapping depend on depth; without one it is a homography, the
  // same for every frame: computed once per thread and camera pair.
  cv::Mat depth;
  if (t.norm() > 0) depth = LoadDepthMeters(sequence, frame);
  thread_local std::vector<double> fixed_key;
  thread_local cv::Mat fixed_x, fixed_y;
  const Eigen::Matrix4d m = camera.color_from_depth.matrix();
  std::vector<double> key = {kd.fx, kd.fy, kd.cx, kd.cy, double(kd.width), double(kd.height),
                             kc.fx, kc.fy, kc.cx, kc.cy};
  key.insert(key.end(), m.data(), m.data() + 16);
  key.insert(key.end(), kc.distortion.begin(), kc.distortion.end());
  const bool distorted = kc.HasDistortion();
  const bool fixed = depth.empty();
  if (fixed && key == fixed_key) {
    cv::Mat out;
    cv::remap(color, out, fixed_x, fixed_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    return out;
  }
  cv::Mat map_x(kd.height, kd.width, CV_32F), map_y(kd.height, kd.width, CV_32F);
  for (int v = 0; v < kd.height; ++v) {
    for (int u = 0; u < kd.width; ++u) {
      const Eigen::Vector3d ray((u - kd.cx) / kd.fx, (v - kd.cy) / kd.fy, 1.0);
      const float z = depth.empty() ? 0.0f : depth.at<float>(v, u);
      const Eigen::Vector3d p = z > 0 ? Eigen::Vector3d(r * (z * ray) + t) : Eigen::Vector3d(r * ray);
      const bool ahead = p.z() > 1e-9;
      // The pinhole pixel, then where the colour camera's lens put it in the stored image.
      Eigen::Vector2d at(kc.fx * p.x() / p.z() + kc.cx, kc.fy * p.y() / p.z() + kc.cy);
      if (ahead && distorted) at = kc.Distort(at.x(), at.y());
      map_x.at<float>(v, u) = ahead ? static_cast<float>(at.x()) : -1.0f;
      map_y.at<float>(v, u) = ahead ? static_cast<float>(at.y()) : -1.0f;
    }
  }
  if (fixed) fixed_key = key, fixed_x = map_x, fixed_y = map_y;
  cv::Mat out;
  cv::remap(color, out, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace

void RequireSomeValidDepth(const RgbdSequence& sequence) {
  const size_t n = sequence.frames.size();
  if (n == 0) return;
  auto has_depth = [&](size_t k) { return cv::countNonZero(LoadDepthMeters(sequence, sequence.frames[k]) > 0) > 0; };
  std::vector<bool> seen(n, false);
  for (size_t s = 0; s < 5; ++s) {  // first, last and three between
    const size_t k = s * (n - 1) / 4;
    if (seen[k]) continue;
    seen[k] = true;
    if (has_depth(k)) return;
  }
  for (size_t k = 0; k < n; ++k) {
    if (!seen[k] && has_depth(k)) return;
  }
  ThrowInputError(sequence.root, fmt::format("none of its {} depth images holds a valid depth (all zero or an invalid "
                                             "value; the first is {})",
                                             n, sequence.frames.front().depth_path.string()));
}

namespace {

// Depth of the depth camera forward-warped into the colour camera: each depth pixel's
// footprint (its corners' points at its depth, projected) filled with its point's depth in
// the colour camera, the nearest kept where footprints overlap (a z-buffer); colour pixels no
// depth pixel lands on stay 0 (no depth), never interpolated across an edge.
cv::Mat WarpDepthIntoColor(const cv::Mat& depth, const DepthCamera& camera, const CameraIntrinsics& kc) {
  const CameraIntrinsics& kd = camera.intrinsics;
  const Eigen::Matrix3d r = camera.color_from_depth.linear();
  const Eigen::Vector3d t = camera.color_from_depth.translation();
  cv::Mat out(kc.height, kc.width, CV_32F, cv::Scalar(0));
  auto project = [&](double u, double v, double z, double* x, double* y) {
    const Eigen::Vector3d p = r * Eigen::Vector3d((u - kd.cx) * z / kd.fx, (v - kd.cy) * z / kd.fy, z) + t;
    if (p.z() <= 1e-6) return false;
    *x = kc.fx * p.x() / p.z() + kc.cx;
    *y = kc.fy * p.y() / p.z() + kc.cy;
    return true;
  };
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u) {
      const double z = row[u];
      if (!(z > 0)) continue;
      double xa, ya, xb, yb, xc, yc;
      if (!project(u - 0.5, v - 0.5, z, &xa, &ya) || !project(u + 0.5, v + 0.5, z, &xb, &yb) ||
          !project(u, v, z, &xc, &yc)) {
        continue;
      }
      const Eigen::Vector3d p = r * kd.Unproject(u, v, z) + t;
      // Colour pixels whose centres the footprint covers; the centre's pixel where it covers none.
      int x0 = static_cast<int>(std::ceil(std::min(xa, xb))), x1 = static_cast<int>(std::ceil(std::max(xa, xb))) - 1;
      int y0 = static_cast<int>(std::ceil(std::min(ya, yb))), y1 = static_cast<int>(std::ceil(std::max(ya, yb))) - 1;
      if (x0 > x1) x0 = x1 = static_cast<int>(std::lround(xc));
      if (y0 > y1) y0 = y1 = static_cast<int>(std::lround(yc));
      x0 = std::max(x0, 0), y0 = std::max(y0, 0);
      x1 = std::min(x1, kc.width - 1), y1 = std::min(y1, kc.height - 1);
      const auto zc = static_cast<float>(p.z());
      for (int y = y0; y <= y1; ++y) {
        float* o = out.ptr<float>(y);
        for (int x = x0; x <= x1; ++x) {
          if (o[x] == 0 || zc < o[x]) o[x] = zc;
        }
      }
    }
  }
  return out;
}

}  // namespace

cv::Mat LoadDepthMeters(const RgbdSequence& sequence, const RgbdFrame& frame) {
  if (sequence.depth_camera) {
    // The depth camera's own depth, then warped into the colour camera (--align-to color).
    RgbdSequence depth_view;
    depth_view.intrinsics = sequence.depth_camera->intrinsics;
    depth_view.intrinsics_source = sequence.intrinsics_source;
    depth_view.depth_scale = sequence.depth_scale;
    depth_view.invalid_depth_values = sequence.invalid_depth_values;
    depth_view.depth_encoding = sequence.depth_encoding;
    CameraIntrinsics pinhole = *depth_view.intrinsics;
    pinhole.distortion = {};
    return WarpDepthIntoColor(LoadDepthMeters(depth_view, frame),
                              DepthCamera{pinhole, sequence.depth_camera->color_from_depth}, *sequence.intrinsics);
  }
  const cv::Mat raw = ReadFrameImage(frame.depth_path, frame.depth_embedded, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.depth() == CV_8U) {
    ThrowInputError(frame.depth_path, "depth image is 8-bit; expected 16-bit");
  }
  if (raw.type() != CV_16UC1) {
    ThrowInputError(frame.depth_path,
                    fmt::format("depth image has {} channels of type {}; expected 16-bit single channel",
                                raw.channels(), raw.depth()));
  }
  if (sequence.intrinsics && (raw.cols != sequence.intrinsics->width || raw.rows != sequence.intrinsics->height)) {
    ThrowInputError(frame.depth_path,
                    fmt::format("depth image is {}x{} but the intrinsics ({}) are for {}x{}", raw.cols, raw.rows,
                                sequence.intrinsics_source, sequence.intrinsics->width, sequence.intrinsics->height));
  }
  // Every stored value's metres, once per sequence layout (a 256 KiB table): decoding,
  // invalid values and scale in one look-up per pixel.
  thread_local std::vector<float> table;
  thread_local std::tuple<DepthEncoding, double, std::vector<uint16_t>> table_for;
  const auto key = std::make_tuple(sequence.depth_encoding, sequence.depth_scale, sequence.invalid_depth_values);
  if (table.empty() || table_for != key) {
    table.resize(65536);
    const auto& invalid = sequence.invalid_depth_values;
    for (int raw_value = 0; raw_value < 65536; ++raw_value) {
      const uint16_t v = DecodeDepthValue(static_cast<uint16_t>(raw_value), sequence.depth_encoding);
      const bool bad = std::find(invalid.begin(), invalid.end(), v) != invalid.end();
      table[raw_value] = bad ? 0.0f : static_cast<float>(v * sequence.depth_scale);
    }
    table_for = key;
  }
  cv::Mat depth(raw.size(), CV_32F);
  for (int y = 0; y < raw.rows; ++y) {
    const uint16_t* in = raw.ptr<uint16_t>(y);
    float* out = depth.ptr<float>(y);
    for (int x = 0; x < raw.cols; ++x) out[x] = table[in[x]];
  }
  if (sequence.intrinsics) return UndistortImage(depth, *sequence.intrinsics, cv::INTER_NEAREST);
  return depth;
}

cv::Mat UndistortImage(const cv::Mat& image, const CameraIntrinsics& intrinsics, int interpolation) {
  if (!intrinsics.HasDistortion()) return image;
  // Per pinhole pixel, where it lies in the stored image. Float maps for nearest neighbour
  // (OpenCV rounds them); fixed-point ones for bilinear (OpenCV's fast path). Outside the
  // stored image: depth 0 (invalid), colour its nearest edge pixel (image.h).
  struct Maps {
    std::array<double, 9> key{};
    cv::Mat x, y, fixed_xy, fixed_weights;
  };
  thread_local Maps maps;
  const std::array<double, 9> key{intrinsics.fx,
                                  intrinsics.fy,
                                  intrinsics.cx,
                                  intrinsics.cy,
                                  intrinsics.distortion[0],
                                  intrinsics.distortion[1],
                                  intrinsics.distortion[2],
                                  intrinsics.distortion[3],
                                  intrinsics.distortion[4]};
  if (maps.x.size() != image.size() || maps.key != key) {
    maps.key = key;
    maps.x.create(image.size(), CV_32F);
    maps.y.create(image.size(), CV_32F);
    for (int v = 0; v < image.rows; ++v) {
      for (int u = 0; u < image.cols; ++u) {
        const Eigen::Vector2d d = intrinsics.Distort(u, v);
        maps.x.at<float>(v, u) = static_cast<float>(d.x());
        maps.y.at<float>(v, u) = static_cast<float>(d.y());
      }
    }
    cv::convertMaps(maps.x, maps.y, maps.fixed_xy, maps.fixed_weights, CV_16SC2);
  }
  cv::Mat out;
  if (interpolation == cv::INTER_NEAREST) {
    cv::remap(image, out, maps.x, maps.y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar());
  } else {
    cv::remap(image, out, maps.fixed_xy, maps.fixed_weights, interpolation, cv::BORDER_REPLICATE);
  }
  return out;
}

namespace {

cv::Mat LoadColorAs(const RgbdSequence& sequence, const RgbdFrame& frame, cv::Size depth_size, int flags) {
  cv::Mat color = ReadFrameImage(frame.color_path, frame.color_embedded, flags);
  if (sequence.color_camera && sequence.intrinsics) {
    const CameraIntrinsics& kc = sequence.color_camera->intrinsics;
    if (color.cols != kc.width || color.rows != kc.height) {
      ThrowInputError(frame.color_path, fmt::format("colour image is {}x{} but the colour camera's intrinsics are for "
                                                    "{}x{}",
                                                    color.cols, color.rows, kc.width, kc.height));
    }
    return ColorIntoDepthCamera(sequence, frame, color);
  }
  if (!depth_size.empty() && color.size() != depth_size) {
    ThrowInputError(frame.color_path,
                    fmt::format("colour image is {}x{} but its depth image {} is {}x{}", color.cols, color.rows,
                                frame.depth_path.filename().string(), depth_size.width, depth_size.height));
  }
  return color;
}

}  // namespace

cv::Mat LoadColor(const RgbdSequence& sequence, const RgbdFrame& frame, cv::Size depth_size) {
  const cv::Mat color = LoadColorAs(sequence, frame, depth_size, cv::IMREAD_COLOR);
  if (sequence.color_camera) return color;  // already in the (pinhole) depth camera
  return sequence.intrinsics ? UndistortImage(color, *sequence.intrinsics, cv::INTER_LINEAR) : color;
}

cv::Mat LoadGray(const RgbdSequence& sequence, const RgbdFrame& frame, cv::Size depth_size) {
  const cv::Mat gray = LoadColorAs(sequence, frame, depth_size, cv::IMREAD_GRAYSCALE);
  if (sequence.color_camera) return gray;
  return sequence.intrinsics ? UndistortImage(gray, *sequence.intrinsics, cv::INTER_LINEAR) : gray;
}

}  // namespace f2c
