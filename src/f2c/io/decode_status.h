#pragma once
// What a fast image decoder (png.h, jpeg.h) made of the bytes it was given.

namespace f2c {

enum class DecodeStatus {
  kDecoded,     // *out holds the image
  kNotHandled,  // not a kind this decoder takes: ask OpenCV
  kCorrupt,     // damaged; *problem says how, in a user's words
};

}  // namespace f2c
