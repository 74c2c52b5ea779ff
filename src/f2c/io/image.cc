#include "f2c/io/image.h"

#include <fmt/format.h>

#include <algorithm>
#include <opencv2/imgcodecs.hpp>

#include "f2c/util/error.h"

namespace f2c {
namespace {

cv::Mat Decode(const std::filesystem::path& path, int flags) {
  if (!std::filesystem::is_regular_file(path)) ThrowInputError(path, "missing frame image");
  cv::Mat image;
  try {
    image = cv::imread(path.string(), flags);
  } catch (const cv::Exception&) {
    image.release();
  }
  if (image.empty()) ThrowInputError(path, "cannot decode image (corrupt or not an image)");
  return image;
}

}  // namespace

cv::Mat LoadDepthMeters(const RgbdSequence& sequence, const RgbdFrame& frame) {
  const cv::Mat raw = Decode(frame.depth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
  if (raw.depth() == CV_8U) {
    ThrowInputError(frame.depth_path, "depth image is 8-bit; expected 16-bit");
  }
  if (raw.type() != CV_16UC1) {
    ThrowInputError(frame.depth_path,
                    fmt::format("depth image has {} channels of type {}; expected 16-bit single channel",
                                raw.channels(), raw.depth()));
  }
  if (sequence.intrinsics &&
      (raw.cols != sequence.intrinsics->width || raw.rows != sequence.intrinsics->height)) {
    ThrowInputError(frame.depth_path,
                    fmt::format("depth image is {}x{} but the intrinsics ({}) are for {}x{}", raw.cols,
                                raw.rows, sequence.intrinsics_source, sequence.intrinsics->width,
                                sequence.intrinsics->height));
  }
  cv::Mat depth(raw.size(), CV_32F);
  const auto& invalid = sequence.invalid_depth_values;
  for (int y = 0; y < raw.rows; ++y) {
    const uint16_t* in = raw.ptr<uint16_t>(y);
    float* out = depth.ptr<float>(y);
    for (int x = 0; x < raw.cols; ++x) {
      const uint16_t v = DecodeDepthValue(in[x], sequence.depth_encoding);
      const bool bad = std::find(invalid.begin(), invalid.end(), v) != invalid.end();
      out[x] = bad ? 0.0f : static_cast<float>(v * sequence.depth_scale);
    }
  }
  return depth;
}

cv::Mat LoadColor(const RgbdFrame& frame, cv::Size depth_size) {
  cv::Mat color = Decode(frame.color_path, cv::IMREAD_COLOR);
  if (!depth_size.empty() && color.size() != depth_size) {
    ThrowInputError(frame.color_path,
                    fmt::format("colour image is {}x{} but its depth image {} is {}x{}", color.cols,
                                color.rows, frame.depth_path.filename().string(), depth_size.width,
                                depth_size.height));
  }
  return color;
}

}  // namespace f2c
