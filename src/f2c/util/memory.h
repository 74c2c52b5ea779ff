#pragma once
// Memory use of this process, for run.json and benchmarks.

#include <cstdint>

namespace f2c {

// Peak resident set size so far (bytes; Linux VmHWM), 0 where unknown.
int64_t PeakResidentBytes();
// Current resident set size (bytes; Linux VmRSS), 0 where unknown.
int64_t ResidentBytes();

}  // namespace f2c
