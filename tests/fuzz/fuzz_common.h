#pragma once
// What every fuzz target shares (tests/fuzz/, bench/fuzz.sh): the bytes written to a file in
// a private folder, since the readers take paths, and the one outcome a reader may have
// besides success: an InputError (one line naming the file). Any other exception, a crash or
// a sanitizer report is a finding.

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "f2c/util/error.h"

namespace f2c::fuzz {

// A folder of this process's own under /dev/shm (memory), made once.
inline const std::filesystem::path& Scratch() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d = std::filesystem::path("/dev/shm") / ("f2c_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::filesystem::path WriteInput(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = Scratch() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

// Runs `read`; an InputError is the expected refusal of bad input.
template <typename F>
void Expect(F&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
}

}  // namespace f2c::fuzz
