#pragma once
// The benchmarks' access to ../shared/data: a sequence by folder name, or a note on stderr
// and nothing when it is absent (benchmarks skip what they cannot measure).

#include <cstdio>
#include <filesystem>
#include <optional>

#include "f2c/io/sequence.h"

namespace f2c::bench {

// TUM folders (an rgb.txt) get the fr1 intrinsics, the only TUM camera in the data.
inline std::optional<RgbdSequence> OpenSequence(const std::filesystem::path& data, const char* name) {
  const std::filesystem::path dir = data / name;
  if (!std::filesystem::exists(dir)) {
    std::fprintf(stderr, "skip %s: %s absent\n", name, dir.string().c_str());
    return std::nullopt;
  }
  IoOptions io;
  if (std::filesystem::exists(dir / "rgb.txt")) io.intrinsics = "tum-fr1";
  return ReadSequence(dir, io);
}

}  // namespace f2c::bench
