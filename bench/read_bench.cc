// How fast a dataset or recording reads, and how much memory that takes: opens INPUT as
// register does, then decodes every frame's depth and colour (LoadDepthMeters, LoadColor),
// one after another on one thread. Prints one markdown table row: frames, seconds to open,
// frames per second decoded, the input's size and the process's peak resident memory.
//   ./build/bench/read_bench INPUT LABEL [--intrinsics ...]

#include <cstdio>
#include <filesystem>
#include <string>

#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/util/error.h"
#include "f2c/util/memory.h"
#include "f2c/util/timer.h"

int main(int argc, char** argv) {
  using namespace f2c;
  if (argc < 3) {
    std::fprintf(stderr, "usage: read_bench INPUT LABEL [--intrinsics ...]\n");
    return 2;
  }
  try {
    IoOptions io;
    if (argc > 4 && std::string(argv[3]) == "--intrinsics") io.intrinsics = argv[4];
    Timer open;
    const RgbdSequence seq = ReadSequence(argv[1], io);
    const double open_s = open.Seconds();
    Timer decode;
    for (const RgbdFrame& f : seq.frames) {
      const cv::Mat depth = LoadDepthMeters(seq, f);
      LoadColor(seq, f, depth.size());
    }
    const double fps = seq.frames.size() / decode.Seconds();
    uint64_t bytes = 0;
    const std::filesystem::path input = argv[1];
    if (std::filesystem::is_regular_file(input)) {
      bytes = std::filesystem::file_size(input);
    } else {
      for (const auto& e : std::filesystem::recursive_directory_iterator(input)) {
        if (e.is_regular_file()) bytes += e.file_size();
      }
    }
    std::printf("| %s | %zu | %.2f | %.1f | %.2f | %.0f |\n", argv[2], seq.frames.size(), open_s, fps, bytes / 1e9,
                PeakResidentBytes() / 1048576.0);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
