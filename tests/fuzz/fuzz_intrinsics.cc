// Intrinsics: the --intrinsics text, a 3x3 matrix file (7-Scenes, 3DMatch) and Open3D's JSON.
#include "f2c/geometry/intrinsics.h"
#include "f2c/io/readers.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  f2c::fuzz::Expect([&] { f2c::ParseIntrinsics(bytes, "--intrinsics"); });
  const auto matrix = f2c::fuzz::WriteInput("camera-intrinsics.txt", bytes);
  f2c::fuzz::Expect([&] { f2c::ReadIntrinsicsMatrixFile(matrix); });
  const auto json = f2c::fuzz::WriteInput("camera_intrinsic.json", bytes);
  f2c::fuzz::Expect([&] { f2c::internal::ReadOpen3dIntrinsics(json); });
  return 0;
}
