#include "f2c/optim/blas_threads.h"

#include <dlfcn.h>

#include <cstdlib>
#include <initializer_list>

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

bool UseSerialOpenMp() {
  for (const char* name : {"OMP_NUM_THREADS", "OMP_THREAD_LIMIT", "OMP_MAX_ACTIVE_LEVELS"}) {
    if (std::getenv(name) != nullptr) return false;  // the user's choice
  }
  using SetLevels = void (*)(int);
  auto set_levels = reinterpret_cast<SetLevels>(dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"));
  if (set_levels == nullptr) return false;
  set_levels(0);
  return true;
}

int OpenMpMaxActiveLevels() {
  using GetLevels = int (*)();
  auto get_levels = reinterpret_cast<GetLevels>(dlsym(RTLD_DEFAULT, "omp_get_max_active_levels"));
  return get_levels == nullptr ? -1 : get_levels();
}

}  // namespace f2c
