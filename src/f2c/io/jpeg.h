#pragma once
// JPEG colour through TurboJPEG, straight to BGR: OpenCV 4.6 decodes to RGB and swaps the
// channels in a second pass, which made colour decoding half again as slow (2.2 against
// 1.4 ms per VGA frame). The pixels are the same as OpenCV's (the same libjpeg-turbo, the
// same accurate DCT and smooth upsampling); the tests hold it to that.

#include <opencv2/core.hpp>
#include <string_view>

namespace f2c {

// Decodes a baseline or progressive YCbCr, RGB or grey JPEG into 8-bit BGR (*out). False,
// with *out untouched, for anything else (CMYK, an EXIF orientation OpenCV would apply, a
// damaged stream): the caller then asks OpenCV.
bool DecodeJpegBgr(std::string_view bytes, cv::Mat* out);

}  // namespace f2c
