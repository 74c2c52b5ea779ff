#!/usr/bin/env bash
# Sets up and builds, then either
#   bash scripts/demo.sh                 fine2coarse demo: simulate an apartment scan,
#                                        register it, evaluate it (no data needed)
#   bash scripts/demo.sh DATASET [OUTDIR] [register options...]
#                                        register a dataset folder into T0 and evaluate it
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ]; then
  bash scripts/build.sh
  exec ./build/apps/fine2coarse demo
fi
input="$1"
out="${2:-out/$(basename "$input")}"
shift $(( $# > 2 ? 2 : $# ))
extra=("$@")
if [ ${#extra[@]} -eq 0 ] && [ -f "$input/rgb.txt" ]; then extra=(--intrinsics tum-fr1); fi
bash scripts/build.sh
./build/apps/fine2coarse register "$input" -o "$out" "${extra[@]}"
./build/apps/fine2coarse evaluate --estimate "$out/trajectory.txt" --ground-truth "$input"
