// ScanNet .sens recordings as register reads them: the header and frame index, then the
// first and last frames' depth and colour (raw, zlib, PNG or JPEG; colour resampled into the
// depth camera where the recording has two).
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = f2c::fuzz::WriteInput("scan.sens", {reinterpret_cast<const char*>(data), size});
  f2c::fuzz::Expect([&] {
    const f2c::RgbdSequence seq = f2c::ReadSequence(path);
    for (const f2c::RgbdFrame* frame : {&seq.frames.front(), &seq.frames.back()}) {
      const cv::Mat depth = f2c::LoadDepthMeters(seq, *frame);
      f2c::LoadColor(seq, *frame, depth.size());
    }
  });
  return 0;
}
