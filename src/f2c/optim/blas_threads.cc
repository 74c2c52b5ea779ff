#include "f2c/optim/blas_threads.h"

#include <dlfcn.h>

#include <cstdlib>

namespace f2c {

// Looked up at run time: the BLAS is chosen by the system (Debian's alternatives), not at
// link time, and only OpenBLAS has these functions.
bool UseOneBlasThread() {
  if (std::getenv("OPENBLAS_NUM_THREADS") != nullptr) return false;  // the user's choice
  using SetThreads = void (*)(int);
  auto set_threads = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set_threads == nullptr) return false;
  set_threads(1);
  return true;
}

int BlasThreads() {
  using GetThreads = int (*)();
  auto get_threads = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  return get_threads == nullptr ? -1 : get_threads();
}

}  // namespace f2c
