#!/usr/bin/env bash
# Fuzzes every reader with libFuzzer (tests/fuzz/): builds the targets with clang, AddressSanitizer
# and UndefinedBehaviorSanitizer into build-fuzz/, then runs each for SECONDS on a copy of
# its seed corpus (tests/fuzz/corpus/<target>/) and prints a table: executions, coverage
# (libFuzzer's edge count), corpus growth and findings. Crash inputs are kept in
# WORK/<target>/ (crash-*, leak-*, timeout-*).
#
#   bash bench/fuzz.sh [SECONDS=60] [WORK=/tmp/f2c-fuzz] [JOBS=2]
#   F2C_FUZZ_TARGETS="fuzz_caches" bash bench/fuzz.sh 600
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
work="${2:-/tmp/f2c-fuzz}"
jobs="${3:-2}"
# F2C_FUZZ_TARGETS="fuzz_caches fuzz_ply": only these.
read -r -a targets <<< "${F2C_FUZZ_TARGETS:-fuzz_trajectory fuzz_correspondences fuzz_intrinsics fuzz_tum_lists fuzz_caches fuzz_images fuzz_ply fuzz_recordings}"
command -v clang++ > /dev/null || { echo "error: clang++ not found (Debian: clang, libclang-rt-14-dev)" >&2; exit 1; }
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++ -DF2C_FUZZ=ON \
  -DF2C_BUILD_TESTS=OFF -DF2C_BUILD_BENCH=OFF > /dev/null
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]}"
mkdir -p "$work"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
run() {  # target
  local t="$1" dir="$work/$1"
  rm -rf "$dir"
  mkdir -p "$dir/corpus"
  cp tests/fuzz/corpus/"$t"/* "$dir/corpus/"
  local seeds
  seeds=$(ls "$dir/corpus" | wc -l)
  # -max_len: the largest seed (a feature cache is tens of KB), at least 4 KB.
  local max_len
  max_len=$(find "$dir/corpus" -type f -printf '%s\n' | sort -n | tail -1)
  max_len=$((max_len > 4096 ? max_len + 1024 : 4096))
  (cd "$dir" && "$OLDPWD/build-fuzz/tests/fuzz/$t" corpus -max_total_time="$seconds" -max_len="$max_len" \
    -timeout=10 -rss_limit_mb=4096 -print_final_stats=1 > log.txt 2>&1) || true
  local execs cov units findings
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$dir/log.txt" | tail -1 | grep -o '[0-9]*$' || echo "?")
  cov=$(grep -o 'cov: [0-9]*' "$dir/log.txt" | tail -1 | grep -o '[0-9]*' || echo "?")
  units=$(ls "$dir/corpus" | wc -l)
  findings=$(ls "$dir" | grep -cE '^(crash|leak|timeout|oom)-' || true)
  printf '| %s | %s | %s | %s | %s -> %s | %s |\n' "$t" "$seconds" "$execs" "$cov" "$seeds" "$units" "$findings" > "$dir/row.md"
}
export -f run
export seconds work
printf '%s\n' "${targets[@]}" | xargs -P "$jobs" -I{} bash -c 'run {}'
echo "| target | seconds | executions | coverage (edges) | corpus | findings |"
echo "|---|---|---|---|---|---|"
for t in "${targets[@]}"; do cat "$work/$t/row.md"; done
for t in "${targets[@]}"; do
  for f in "$work/$t"/crash-* "$work/$t"/timeout-* "$work/$t"/oom-*; do
    [ -e "$f" ] && echo "finding: $f" && grep -m3 -E "ERROR|runtime error|terminate|what\(\)" "$work/$t/log.txt" | sed 's/^/  /'
  done
done
exit 0
