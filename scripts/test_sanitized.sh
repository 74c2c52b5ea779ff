#!/usr/bin/env bash
# The whole test suite built with AddressSanitizer and UndefinedBehaviorSanitizer, into
# build-sanitize/. Any report (a bad read or write, a use after free, signed overflow, a
# misaligned or null access, ...) aborts the test that triggered it, so ctest fails.
# LeakSanitizer is off: OpenCV's and TBB's process-lifetime caches are reported as leaks at
# exit, which is noise, not our bug.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=Release -DF2C_SANITIZE=address,undefined \
  -DF2C_BUILD_BENCH=OFF > /dev/null
cmake --build build-sanitize -j "$(nproc)"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-sanitize --output-on-failure -j "$(nproc)"
