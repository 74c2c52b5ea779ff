#!/usr/bin/env bash
# The whole test suite built with AddressSanitizer and UndefinedBehaviorSanitizer (clang, -O2)
# into build-sanitize/, then every libFuzzer target (tests/fuzz/) from the same
# build for a few seconds on its seed corpus. Any report (a bad read or write, a use after
# free, signed overflow, a misaligned or null access, a fuzz crash) fails the script.
# LeakSanitizer is off: OpenCV's and TBB's process-lifetime caches are reported as leaks at
# exit, which is noise, not our bug.
#
#   bash scripts/test_sanitized.sh [FUZZ_SECONDS=5]
set -euo pipefail
cd "$(dirname "$0")/.."
fuzz_seconds="${1:-5}"
bash scripts/setup.sh
# A build folder left by an older g++ sanitizer build cannot switch compilers in place.
if [ -f build-sanitize/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' build-sanitize/CMakeCache.txt; then
  rm -rf build-sanitize
fi
# clang compiles this code about twice as fast as g++. -O2: at -O1 with assertions the suite
# ran 12x slower than the plain build (15 minutes; BENCHMARKS.md). F2C_CHECK ignores NDEBUG.
cmake -S . -B build-sanitize -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Sanitize \
  -DCMAKE_CXX_FLAGS_SANITIZE="-O2 -DNDEBUG" -DF2C_SANITIZE=address,undefined -DF2C_FUZZ=ON \
  -DF2C_BUILD_BENCH=OFF > /dev/null
cmake --build build-sanitize -j "$(nproc)"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
ctest --test-dir build-sanitize --output-on-failure -j "$(nproc)"

# Fuzz smoke run: each target replays its corpus, then mutates it for FUZZ_SECONDS, as many
# targets at a time as there are cores. A crash leaves crash-* in the work folder and a non-zero
# exit.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fuzz_one() {
  local t=$1
  mkdir -p "$work/$t/corpus"
  cp tests/fuzz/corpus/"$t"/* "$work/$t/corpus/"
  if (cd "$work/$t" && "$OLDPWD/build-sanitize/tests/fuzz/$t" corpus -max_total_time="$fuzz_seconds" \
        -max_len=65536 -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 > log.txt 2>&1); then
    echo "fuzz: $t: $(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$t/log.txt" |
      grep -o '[0-9]*$') runs, no finding" > "$work/$t/result.txt"
  else
    { echo "fuzz: $t: FAILED"
      grep -m5 -E "ERROR|runtime error|terminate|what\(\)|Test unit written" "$work/$t/log.txt" ||
        tail -20 "$work/$t/log.txt"; } > "$work/$t/result.txt"
    return 1
  fi
}
targets=()
for src in tests/fuzz/fuzz_*.cc; do targets+=("$(basename "$src" .cc)"); done
failed=0
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$(nproc)" ]; then
    wait -n || failed=1
    running=$((running - 1))
  fi
  fuzz_one "$t" &
  running=$((running + 1))
done
while [ "$running" -gt 0 ]; do
  wait -n || failed=1
  running=$((running - 1))
done
for t in "${targets[@]}"; do cat "$work/$t/result.txt"; done
exit "$failed"
