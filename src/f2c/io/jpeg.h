#pragma once
// JPEG through TurboJPEG, straight to BGR or grey: OpenCV 4.6 decodes colour to RGB and swaps
// the channels in a second pass, which made colour decoding half again as slow (2.2 against
// 1.4 ms per VGA frame), and it reads a cut-short JPEG with only a libjpeg warning. The
// pixels are the same as OpenCV's (the same libjpeg-turbo, the same accurate DCT and smooth
// upsampling); the tests hold it to that.

#include <opencv2/core.hpp>
#include <string>
#include <string_view>

#include "f2c/io/decode_status.h"

namespace f2c {

// Decodes a baseline or progressive YCbCr, RGB, grey, CMYK or YCCK JPEG into 8-bit BGR, or
// its luminance into 8-bit grey (`grey`; as OpenCV's IMREAD_GRAYSCALE), turned as its EXIF
// orientation says (as OpenCV does for both). kNotHandled, with *out untouched, for anything
// else (not a JPEG, a header TurboJPEG cannot read). kCorrupt when the stream is damaged or
// cut short, even where libjpeg would carry on with a warning and a partly grey image.
DecodeStatus DecodeJpeg(std::string_view bytes, bool grey, cv::Mat* out, std::string* problem = nullptr);

}  // namespace f2c
