// PLY files: fuse's and evaluate's meshes, the simulator's true surfaces.
#include "f2c/io/ply.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = f2c::fuzz::WriteInput("mesh.ply", {reinterpret_cast<const char*>(data), size});
  f2c::fuzz::Expect([&] { f2c::ReadPly(path); });
  return 0;
}
