// OpenCV's image decoders as a library of their own, loaded (dlopen) by DecodeImageFile only
// when a frame is not the PNG or JPEG its own decoders read (PNM, TIFF, BMP, palette or
// interlaced PNG, CMYK JPEG, ...). Linking OpenCV's imgcodecs into every program loads
// GDAL and about 120 other libraries at each start: 0.15 s per process, 0.4 s under
// AddressSanitizer (image.cc). One C function, so that no C++ name crosses dlsym.

#include <cstddef>
#include <opencv2/imgcodecs.hpp>

extern "C" __attribute__((visibility("default"))) int f2c_opencv_imdecode(const unsigned char* bytes, size_t size,
                                                                          int flags, cv::Mat* out) {
  try {
    *out = cv::imdecode(cv::Mat(1, static_cast<int>(size), CV_8U, const_cast<unsigned char*>(bytes)), flags);
  } catch (const cv::Exception&) {
    out->release();
  }
  return out->empty() ? 0 : 1;
}
