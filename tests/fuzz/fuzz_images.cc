// The image decoders every frame goes through: our PNG path, libpng for the other PNG kinds,
// TurboJPEG (CMYK and EXIF orientation too), then OpenCV for the rest (DecodeImageFile), with
// each flag the pipeline uses.
#include <opencv2/imgcodecs.hpp>

#include "f2c/io/image.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = f2c::fuzz::WriteInput("image", {reinterpret_cast<const char*>(data), size});
  const int all_flags[] = {cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR, cv::IMREAD_COLOR, cv::IMREAD_GRAYSCALE};
  for (int flags : all_flags) {
    f2c::fuzz::Expect([&] { f2c::DecodeImageFile(path, flags); });
  }
  return 0;
}
