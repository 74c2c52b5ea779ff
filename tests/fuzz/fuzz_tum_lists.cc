// A TUM folder's lists: the input split at NUL bytes into rgb.txt, depth.txt and
// groundtruth.txt (files are not checked to exist: the lists are what is fuzzed).
#include "f2c/io/sequence.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const std::filesystem::path dir = f2c::fuzz::Scratch() / "tum";
  std::filesystem::create_directories(dir);
  size_t start = 0;
  for (const char* name : {"rgb.txt", "depth.txt", "groundtruth.txt"}) {
    const size_t end = std::min(bytes.find('\0', start), bytes.size());
    f2c::fuzz::WriteInput(std::string("tum/") + name, start <= bytes.size() ? bytes.substr(start, end - start) : "");
    start = end + 1;
  }
  f2c::IoOptions io;
  io.check_files = false;
  io.intrinsics = "tum-fr1";
  f2c::fuzz::Expect([&] { f2c::ReadSequence(dir, io); });
  return 0;
}
