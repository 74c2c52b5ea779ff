// Trajectory files as `evaluate` and `fuse` read them: TUM text, Redwood .log, the authors' .conf.
#include "f2c/io/trajectory.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  for (const char* name : {"t.txt", "t.log", "t.conf"}) {
    const auto path = f2c::fuzz::WriteInput(name, bytes);
    f2c::fuzz::Expect([&] { f2c::ReadTrajectoryFile(path); });
  }
  return 0;
}
