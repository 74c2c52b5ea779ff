// OpenCV's image decoders as a library of their own, loaded (dlopen) by DecodeImageFile only
// when a frame is not the PNG or JPEG its own decoders read (PNM, TIFF, BMP). Linking OpenCV's
// imgcodecs into every program loads GDAL and about 120 other libraries at each start: 0.15 s
// per process, 0.4 s under AddressSanitizer (image.cc). One C function, so that no C++ name
// crosses dlsym.
//
// imdecode reports a damaged file on std::cerr ("imdecode_(''): can't read data: ...") and
// returns an empty image; that line is caught here and its reason handed back, so that the
// user sees one line of ours and nothing else.

#include <cstddef>
#include <cstring>
#include <iostream>
#include <mutex>
#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>

namespace {

// "... error: (-2:Unspecified error) Unexpected end of input stream in function 'readBlock'"
// -> "Unexpected end of input stream"; empty when the text is not of that shape.
std::string ReasonOf(const std::string& text) {
  const size_t code = text.find("error: (");
  if (code == std::string::npos) return {};
  const size_t start = text.find(") ", code);
  if (start == std::string::npos) return {};
  std::string reason = text.substr(start + 2);
  const size_t end = reason.find(" in function");
  if (end != std::string::npos) reason.resize(end);
  while (!reason.empty() && (reason.back() == '\n' || reason.back() == ' ')) reason.pop_back();
  return reason;
}

}  // namespace

// Returns 1 with *out decoded, or 0 with `reason` (NUL-terminated, at most reason_size bytes)
// saying why when OpenCV said.
extern "C" __attribute__((visibility("default"))) int f2c_opencv_imdecode(const unsigned char* bytes, size_t size,
                                                                          int flags, cv::Mat* out, char* reason,
                                                                          size_t reason_size) {
  static std::once_flag silenced;
  std::call_once(silenced, [] { cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT); });
  // std::cerr is ours while OpenCV decodes: nothing else in fine2coarse writes to it.
  static std::mutex cerr_mutex;
  std::ostringstream said;
  {
    const std::lock_guard<std::mutex> lock(cerr_mutex);
    std::streambuf* const previous = std::cerr.rdbuf(said.rdbuf());
    try {
      *out = cv::imdecode(cv::Mat(1, static_cast<int>(size), CV_8U, const_cast<unsigned char*>(bytes)), flags);
    } catch (const cv::Exception& e) {
      out->release();
      said << e.what();
    }
    std::cerr.rdbuf(previous);
  }
  if (!out->empty()) return 1;
  if (reason != nullptr && reason_size > 0) {
    const std::string text = ReasonOf(said.str());
    std::strncpy(reason, text.c_str(), reason_size - 1);
    reason[reason_size - 1] = '\0';
  }
  return 0;
}
