#pragma once
// The BLAS behind Ceres' sparse Cholesky (CHOLMOD, and LAPACK's dpotrf) is OpenBLAS on
// Debian (libblas.so.3 through the alternatives system). By default OpenBLAS starts a thread
// per core and has it spin (sched_yield) between calls, while TBB and Ceres' own threads
// already keep both cores busy. Measured, refinement ms/frame with the
// structure on this 2-core machine:
//   two-rooms-0, another job running:   43-50 with OpenBLAS's threads, 17-19 with one;
//   900-frame walks, machine idle:      within run-to-run noise of each other;
//   2,001-frame walk, machine idle:     11.9-12.4 with its threads, 13.2-13.7 with one.
// So one thread by default: a little slower on an idle machine with a big scan, 2.5 times
// faster when anything else runs. OPENBLAS_NUM_THREADS, when set, is left to decide.

//
// CHOLMOD itself (Debian builds it with OpenMP) opens parallel regions of 4 threads in its
// supernodal factorization for loops that clear or scatter a few thousand entries; on 2
// cores, beside TBB's workers, every region wakes and then spins threads for a
// memset's worth of work (perf: libgomp 6% of the refinement's samples, the kernel's futex
// and scheduling as much again). Measured, the solve with
// those regions on one thread: 15-25% less time, the same poses to the bit.

namespace f2c {

// Asks OpenBLAS, if it is the BLAS loaded, to run its kernels in the calling thread only,
// unless the environment sets OPENBLAS_NUM_THREADS. Idempotent and cheap; a no-op with any
// other BLAS. Returns whether it set the thread count.
bool UseOneBlasThread();

// OpenBLAS's current thread count, or -1 when OpenBLAS is not loaded.
int BlasThreads();

// Asks the OpenMP runtime, if one is loaded, to run every parallel region on the thread that
// meets it (no active levels: omp_set_max_active_levels(0)), unless the environment sets
// OMP_NUM_THREADS, OMP_THREAD_LIMIT or OMP_MAX_ACTIVE_LEVELS. Idempotent; a no-op without
// OpenMP. Returns whether it set it.
bool UseSerialOpenMp();

// The OpenMP runtime's max-active-levels setting, or -1 when none is loaded.
int OpenMpMaxActiveLevels();

}  // namespace f2c
