// ROS 1 bags as register reads them: the bag header, the connections, chunk infos and each
// chunk's index, the topics' images and camera info, then the first and last frames' depth
// and colour (raw, float, PNG or JPEG; from bz2 or lz4 chunks).
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = f2c::fuzz::WriteInput("scan.bag", {reinterpret_cast<const char*>(data), size});
  f2c::fuzz::Expect([&] {
    const f2c::RgbdSequence seq = f2c::ReadSequence(path);
    for (const f2c::RgbdFrame* frame : {&seq.frames.front(), &seq.frames.back()}) {
      const cv::Mat depth = f2c::LoadDepthMeters(seq, *frame);
      f2c::LoadColor(seq, *frame, depth.size());
    }
  });
  return 0;
}
