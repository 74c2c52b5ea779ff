#pragma once
// The BLAS behind Ceres' sparse Cholesky (CHOLMOD, and LAPACK's dpotrf) is OpenBLAS on
// Debian (libblas.so.3 through the alternatives system). By default OpenBLAS starts a thread
// per core and has it spin (sched_yield) between calls, while TBB and Ceres' own threads
// already keep both cores busy. Measured (BENCHMARKS.md), refinement ms/frame with the
// structure on this 2-core machine:
//   two-rooms-0, another job running:   43-50 with OpenBLAS's threads, 17-19 with one;
//   900-frame walks, machine idle:      within run-to-run noise of each other;
//   2,001-frame walk, machine idle:     11.9-12.4 with its threads, 13.2-13.7 with one.
// So one thread by default: a little slower on an idle machine with a big scan, 2.5 times
// faster when anything else runs. OPENBLAS_NUM_THREADS, when set, is left to decide.

namespace f2c {

// Asks OpenBLAS, if it is the BLAS loaded, to run its kernels in the calling thread only,
// unless the environment sets OPENBLAS_NUM_THREADS. Idempotent and cheap; a no-op with any
// other BLAS. Returns whether it set the thread count.
bool UseOneBlasThread();

// OpenBLAS's current thread count, or -1 when OpenBLAS is not loaded.
int BlasThreads();

}  // namespace f2c
