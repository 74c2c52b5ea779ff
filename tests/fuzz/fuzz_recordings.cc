// Recordings as register reads them, whichever their format (found by content, as register
// does): ScanNet .sens (the header and frame index), ROS 1 bags (bag header, connections,
// chunk infos, each chunk's index), ROS 2 .db3 (SQLite) and .mcap (summary, chunk and message
// indexes); then the first and last frames' depth and colour (raw, float, zlib, PNG or JPEG;
// from bz2, lz4 or zstd chunks; colour resampled into the depth camera where there are two).
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = f2c::fuzz::WriteInput("recording", {reinterpret_cast<const char*>(data), size});
  f2c::fuzz::Expect([&] {
    const f2c::RgbdSequence seq = f2c::ReadSequence(path);
    for (const f2c::RgbdFrame* frame : {&seq.frames.front(), &seq.frames.back()}) {
      const cv::Mat depth = f2c::LoadDepthMeters(seq, *frame);
      f2c::LoadColor(seq, *frame, depth.size());
    }
  });
  return 0;
}
