#pragma once
// Decoding colour and depth images, with the checks that make a bad frame an error that
// names the file instead of a crash or silent garbage.

#include <opencv2/core.hpp>

#include "f2c/io/sequence.h"

namespace f2c {

// An image file as OpenCV's imread `flags` ask, through our PNG and JPEG paths first, then
// OpenCV for PNM, TIFF and BMP (and PNG/JPEG kinds ours leave to it); other formats are
// refused. A missing, damaged or oversized (over 32 megapixels) file is an InputError naming it.
cv::Mat DecodeImageFile(const std::filesystem::path& path, int flags);
// The same for bytes already read; `path` names them in errors.
cv::Mat DecodeImageBytes(const std::string& bytes, const std::string& path, int flags);
// A frame's depth or colour image as DecodeImageFile gives it: from its own file, or from
// the part of a recording it is embedded in (raw and zlib-compressed formats too).
cv::Mat ReadFrameImage(const std::filesystem::path& path, const std::optional<EmbeddedImage>& embedded, int flags);
// `size` bytes at `offset` of a file; InputError naming it when they lie past its end.
std::string ReadFileRange(const std::filesystem::path& path, uint64_t offset, uint64_t size);
// An embedded image's stored bytes (from its compressed block where it has one).
std::string ReadEmbeddedBytes(const std::filesystem::path& path, const EmbeddedImage& embedded);

// Depth in metres (CV_32F); invalid pixels are 0. Checks: the file decodes, is 16-bit single
// channel, and has the intrinsics' size when intrinsics are known. When the intrinsics carry
// lens distortion, the depth is resampled to the pinhole model (nearest neighbour: depth is
// never blended across an edge; pixels that map outside the stored image are 0).
cv::Mat LoadDepthMeters(const RgbdSequence& sequence, const RgbdFrame& frame);

// InputError naming the sequence when not one of its depth images holds a valid pixel (all
// zero, or all an invalid value: a wrong depth scale or folder), which would otherwise give
// an identity trajectory and an empty mesh with nothing said. Decodes a few frames spread
// over the sequence and stops at the first with depth; only a sequence whose samples are all
// empty is read whole.
void RequireSomeValidDepth(const RgbdSequence& sequence);

// Colour as 8-bit BGR. Checks that it decodes and that its size equals the depth's
// (`depth_size`, skipped when empty). Resampled to the pinhole model (bilinear) as the depth;
// where that reaches outside the stored image the nearest edge pixel is repeated, so that no
// black rim gives SIFT and the optical flow a corner that does not move with the scene
// (measured: T0's ATE on tum_fr1_xyz_15hz 0.0270 m with a black rim, 0.0236 without).
// Where the colour is another camera (RgbdSequence::color_camera), it is resampled into the
// depth camera instead: each depth pixel takes the colour where its point projects (points
// without depth taken at infinity), so the result has the depth's size and intrinsics.
cv::Mat LoadColor(const RgbdSequence& sequence, const RgbdFrame& frame, cv::Size depth_size = {});
// The colour image decoded straight to 8-bit grey (the same checks and resampling as LoadColor).
cv::Mat LoadGray(const RgbdSequence& sequence, const RgbdFrame& frame, cv::Size depth_size);

// An image of the stored, distorted camera resampled to the pinhole model of `intrinsics`
// (InterpolationFlags: cv::INTER_NEAREST or cv::INTER_LINEAR); the image itself when the
// intrinsics have no distortion. The maps are computed once per thread and calibration.
cv::Mat UndistortImage(const cv::Mat& image, const CameraIntrinsics& intrinsics, int interpolation);

// Decodes one 16-bit value to millimetre-like units per the encoding (before depth_scale).
inline uint16_t DecodeDepthValue(uint16_t v, DepthEncoding encoding) {
  if (encoding == DepthEncoding::kSun3dBitRotated) {
    return static_cast<uint16_t>((v >> 3) | (v << 13));
  }
  return v;
}

}  // namespace f2c
