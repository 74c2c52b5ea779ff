// Ground-truth correspondences in the authors' format.
#include "f2c/io/correspondences.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = f2c::fuzz::WriteInput("correspondences.txt", {reinterpret_cast<const char*>(data), size});
  f2c::fuzz::Expect([&] { f2c::ReadCorrespondences(path); });
  return 0;
}
